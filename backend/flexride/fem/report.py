"""Reduction report: reduced vs full-model frequencies, MAC matrix, mass properties."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from flexride.fem.mac import mac
from flexride.fem.massmatch import InertiaTarget
from flexride.fem.rigid import MassProperties


def mac_matrix(A: np.ndarray, B: np.ndarray, M=None) -> np.ndarray:
    """Modal assurance criterion between the columns of ``A`` and ``B``, mass-weighted when
    ``M`` is given (which makes translations and rotations comparable); see
    :func:`flexride.fem.mac.mac`.
    """
    return mac(A, B, M)


@dataclass
class ReductionReport:
    """What a reduction kept and how well.

    Attributes
    ----------
    body : str
        ``carbody``, ``frame`` or a user model name.
    method : str
        ``guyan``, ``craig-bampton`` or ``modal``.
    cutoff_hz : float
        Cut-off frequency (Hz).
    n_full_dof, n_reduced_dof : int
        Size of the full and the reduced model.
    master_nodes : dict of str to int
        Named master / interface nodes (Guyan, Craig–Bampton).
    reduced_frequencies : list of float
        Retained elastic frequencies (Hz).
    full_frequencies : list of float
        Full-model elastic frequencies up to the cut-off (Hz).
    classification : list of str
        Dominant deformation of each retained mode.
    match : list of int
        Full mode that best matches each reduced mode (by MAC), −1 for none.
    mac : list of list of float or numpy.ndarray
        MAC matrix, reduced (rows) × full (columns), mass-weighted.
    mass : dict
        Mass properties of the model (and of the target, with relative errors).
    guyan_error : list of float, optional
        Error indicator of paper Eq. (9) per reduced mode (Guyan only).
    info : dict
        Method details.
    """

    body: str
    method: str
    cutoff_hz: float
    n_full_dof: int
    n_reduced_dof: int
    master_nodes: dict[str, int] = field(default_factory=dict)
    reduced_frequencies: list[float] = field(default_factory=list)
    full_frequencies: list[float] = field(default_factory=list)
    classification: list[str] = field(default_factory=list)
    match: list[int] = field(default_factory=list)
    mac: list[list[float]] | np.ndarray = field(default_factory=list)
    mass: dict = field(default_factory=dict)
    guyan_error: list[float] | None = None
    info: dict = field(default_factory=dict)

    def frequency_errors(self) -> list[float | None]:
        """Relative error of each reduced frequency against its MAC-matched full mode."""
        out: list[float | None] = []
        for fr, j in zip(self.reduced_frequencies, self.match, strict=False):
            if j < 0 or j >= len(self.full_frequencies):
                out.append(None)
            else:
                out.append(fr / self.full_frequencies[j] - 1.0)
        return out

    def to_dict(self) -> dict:
        """JSON-able dict."""
        return {
            "body": self.body,
            "method": self.method,
            "cutoff_hz": self.cutoff_hz,
            "n_full_dof": self.n_full_dof,
            "n_reduced_dof": self.n_reduced_dof,
            "master_nodes": self.master_nodes,
            "reduced_frequencies_hz": self.reduced_frequencies,
            "full_frequencies_hz": self.full_frequencies,
            "classification": self.classification,
            "match": self.match,
            "frequency_errors": self.frequency_errors(),
            "mac": np.asarray(self.mac, dtype=float).tolist(),
            "mass": self.mass,
            "guyan_error": self.guyan_error,
            "info": self.info,
        }

    @classmethod
    def from_dict(cls, d: dict) -> ReductionReport:
        """Inverse of :meth:`to_dict`."""
        return cls(
            body=d["body"],
            method=d["method"],
            cutoff_hz=d["cutoff_hz"],
            n_full_dof=d["n_full_dof"],
            n_reduced_dof=d["n_reduced_dof"],
            master_nodes=d.get("master_nodes", {}),
            reduced_frequencies=d["reduced_frequencies_hz"],
            full_frequencies=d["full_frequencies_hz"],
            classification=d.get("classification", []),
            match=d.get("match", []),
            mac=d.get("mac", []),
            mass=d.get("mass", {}),
            guyan_error=d.get("guyan_error"),
            info=d.get("info", {}),
        )

    def table(self, max_rows: int = 40) -> str:
        """Readable plain-text table."""
        lines = [
            f"{self.body}: {self.method} reduction, cut-off {self.cutoff_hz:g} Hz, "
            f"{self.n_full_dof} -> {self.n_reduced_dof} DOFs, "
            f"{len(self.reduced_frequencies)} elastic modes kept "
            f"({len(self.full_frequencies)} in the full model)",
        ]
        m = self.mass
        if m:
            lines.append(
                f"mass {m['mass_kg']:.1f} kg, CG ({m['cg_m'][0]:.3f}, {m['cg_m'][1]:.3f}, "
                f"{m['cg_m'][2]:.3f}) m, Ixx/Iyy/Izz "
                + "/".join(f"{v:.1f}" for v in m["inertia_diag_kgm2"])
                + " kg·m²"
            )
            if "errors" in m:
                e = m["errors"]
                lines.append(
                    f"vs target: mass {100 * e['mass']:+.2f} %, Ixx {100 * e['ixx']:+.2f} %, "
                    f"Iyy {100 * e['iyy']:+.2f} %, Izz {100 * e['izz']:+.2f} %"
                )
        head = f"{'mode':>4} {'reduced Hz':>11} {'full Hz':>9} {'error %':>8} {'MAC':>6}"
        if self.guyan_error is not None:
            head += f" {'Eq.9 err':>9}"
        head += "  classification"
        lines.append(head)
        errs = self.frequency_errors()
        for k, fr in enumerate(self.reduced_frequencies[:max_rows]):
            j = self.match[k] if k < len(self.match) else -1
            ff = (
                f"{self.full_frequencies[j]:9.3f}"
                if 0 <= j < len(self.full_frequencies)
                else " " * 9
            )
            err = errs[k]
            er = f"{100 * err:8.2f}" if err is not None else " " * 8
            mac = f"{self.mac[k][j]:6.3f}" if 0 <= j < len(self.full_frequencies) else " " * 6
            row = f"{k + 1:4d} {fr:11.3f} {ff} {er} {mac}"
            if self.guyan_error is not None:
                row += f" {self.guyan_error[k]:9.3g}"
            cls = self.classification[k] if k < len(self.classification) else ""
            lines.append(row + "  " + cls)
        if len(self.reduced_frequencies) > max_rows:
            lines.append(f"... {len(self.reduced_frequencies) - max_rows} more modes")
        return "\n".join(lines)


def mass_summary(props: MassProperties, target: InertiaTarget | None) -> dict:
    """Mass-property block of a report (with relative errors against ``target``)."""
    out = {
        "mass_kg": float(props.mass),
        "cg_m": [float(v) for v in props.cg],
        "inertia_diag_kgm2": [float(v) for v in np.diag(props.inertia)],
        "inertia_kgm2": [[float(v) for v in row] for row in props.inertia],
    }
    if target is not None:
        out["target"] = {
            "mass_kg": float(target.mass),
            "cg_m": [float(v) for v in target.cg],
            "inertia_diag_kgm2": [float(v) for v in target.inertia],
        }
        out["errors"] = target.errors(props)
    return out


def match_modes(mac: np.ndarray, threshold: float = 0.5) -> list[int]:
    """Best full mode (column) for each reduced mode (row); −1 below ``threshold``."""
    if mac.size == 0:
        return [-1] * mac.shape[0]
    j = np.argmax(mac, axis=1)
    return [int(jj) if mac[i, jj] >= threshold else -1 for i, jj in enumerate(j)]
