// Study result: Sperling against speed per condition and point (paper Figs. 14, 17, 22), peak
// acceleration against speed with the fitted line and R² (Fig. 21), flexible against rigid with
// differences in percent (Table 2) and every job's indices; clicking a point opens its job. A
// study with an element-size axis adds its mesh convergence (issue 33, the paper's Fig. 4).

import { api, cached } from "../api.js";
import { h, setChildren, badge, progressBar, fmt, fixed, pct, errorBox, notice, loading, tabs, dataTable, when, DIRECTION_NAMES } from "../components/dom.js";
import { plotCard, loadPlotly } from "../components/plot.js";
import { simpleSelect } from "../components/channels.js";
import { loadPaperPoints, paperPoints, pointCatalogue, pointOrder, pointTag, pointText, pointsCard } from "../components/points.js";
import { facetFigure, flexRigidFigure, facetPanels } from "../components/facets.js";
import { meshSection } from "../components/meshconvergence.js";
import { confirmButton, studyBarStatus } from "./jobs.js";
import { go, replaceQuery } from "../components/nav.js";

const ACTIVE = new Set(["queued", "running"]);

export const groupLabel = (g) => Object.entries(g || {}).map(([k, v]) => (k === "body_model" ? `${v} body` : String(v))).join(" · ") || "all jobs";

const pointsOf = (rows) => pointOrder(rows.map((r) => r.point));

export default async function render(main, ctx) {
  loadPlotly().catch(() => {}); // in parallel with the data
  const id = ctx.params.id;
  ctx.title(`Study ${id.slice(0, 8)}`);
  const head = h("div");
  const body = h("div", {}, loading("Loading the study…"));
  main.append(head, body);
  let timer = null;
  let view = null; // charts, created once
  let lastKey = "";

  async function poll() {
    let st;
    try {
      await loadPaperPoints();
      st = await api.study(id, { signal: ctx.signal });
    } catch (err) {
      if (ctx.signal.aborted) return;
      if (err.status === 404) {
        setChildren(head, h("h1", {}, "Study not found"));
        setChildren(body, notice("error", null, `There is no study ${id}. `, h("a", { href: "#/?tab=studies" }, "Back to the studies.")));
        return;
      }
      setChildren(body, errorBox(err, "Could not load the study"));
      timer = setTimeout(poll, 5000);
      return;
    }
    if (ctx.signal.aborted) return;
    ctx.title(st.name);
    renderHead(st);
    const key = JSON.stringify([st.counts, st.jobs.map((j) => j.status)]);
    const building = st.report && !["ready", "failed"].includes(st.report.state);
    if (!view) view = buildView(st);
    if (key !== lastKey) {
      lastKey = key;
      view.update(st);
    }
    if (ACTIVE.has(st.status) || building) timer = setTimeout(poll, 1500);
  }

  function renderHead(st) {
    const axes = (st.axes || []).map((a) => `${a.name}: ${a.values.map((v) => (typeof v === "number" ? fmt(v) : String(v))).join(", ")}`);
    setChildren(head,
      h("div", { class: "crumbs" }, h("a", { href: "#/?tab=studies" }, "Studies"), " › ", id.slice(0, 8)),
      h("div", { class: "page-head" }, h("h1", {}, st.name, " ", badge(st.status)),
        h("div", { class: "actions" },
          ACTIVE.has(st.status) ? h("button", { type: "button", class: "btn", onclick: async () => {
            try {
              await api.cancelStudy(id);
              poll();
            } catch (err) {
              setChildren(body, errorBox(err, "Could not cancel"));
            }
          } }, "Cancel study") : null,
          h("a", { class: "btn", href: `#/?study=${id}` }, "Its jobs"),
          confirmButton("Delete", "Confirm delete", async () => {
            try {
              await api.deleteStudy(id);
              go("/?tab=studies");
            } catch (err) {
              setChildren(body, errorBox(err, "Could not delete"));
            }
          }))),
      st.description ? h("p", { class: "muted" }, st.description) : null,
      h("div", { class: "card" }, h("div", { class: "row" },
        h("div", { class: "grow" }, progressBar(st.progress, "Study progress", studyBarStatus(st))),
        h("span", { id: "study-counts" }, `${st.n_jobs} jobs: ${Object.entries(st.counts).map(([k, v]) => `${v} ${k}`).join(", ") || "none"}`)),
      h("p", { class: "small muted" }, axes.join(" · "), ` · created ${when(st.created_at)}`)),
      st.report ? reportCard(st.report) : null);
  }

  /** The report of a paper report study: its state, and "Open report" once it is built. */
  function reportCard(rep) {
    const verdicts = Object.entries(rep.counts || {}).map(([k, v]) => `${v} ${k}`).join(", ");
    const state = {
      waiting: `Waiting for the runs: ${rep.message}.`,
      queued: "Every run has finished; the report's build is queued.",
      running: `Building the report: ${rep.message} (${Math.round(100 * (rep.progress || 0))} %).`,
      ready: `The report is ready${verdicts ? ` (claims: ${verdicts})` : ""}.`,
      failed: `No report: ${rep.error || rep.message}.`,
    }[rep.state] || rep.message;
    return h("section", { class: "card", id: "study-report", "aria-labelledby": "study-report-title" },
      h("h2", { id: "study-report-title" }, "Paper report ", h("span", { class: `badge st-${{ ready: "succeeded", waiting: "queued" }[rep.state] || rep.state}` }, rep.state)),
      h("p", { id: "study-report-state" }, state),
      rep.state === "ready" ? h("div", { class: "actions" },
        h("a", { class: "btn btn-primary", id: "open-report", href: rep.links.html, target: "_blank", rel: "noopener" }, "Open report"),
        h("a", { class: "btn", id: "report-summary", href: rep.links.summary, target: "_blank", rel: "noopener" }, "Claims (summary.json)")) : null,
      rep.state === "running" || rep.state === "queued" ? progressBar(rep.progress || 0, "Report build") : null);
  }

  function buildView(st0) {
    const notesEl = h("div");
    const meshEl = h("div");
    let mesh = null; // the mesh-convergence section, made when the study has such tables
    const sectionsEl = h("div");
    const pointsBox = h("div");
    const state = { dir: ["z", "y"].includes(ctx.query.dir) ? ctx.query.dir : "both", points: null, frQ: "sperling", tablePoint: "" };
    let st = st0;
    let catalogue = pointCatalogue();
    let catalogueFrom = null;
    const sync = () => replaceQuery({ tab: state.tab, dir: state.dir === "both" ? "" : state.dir });
    const dirs = () => (state.dir === "both" ? ["z", "y"] : [state.dir]);
    const seedsAxis = () => (st.axes || []).find((a) => a.name === "seed");
    /** What the error bars are, when the study has irregularity realisations. */
    const ciNote = (extra = "") => {
      const ax = seedsAxis();
      return ax && ax.values.length > 1 ? ` Values are means over ${ax.values.length} irregularity realisations; error bars the 95 % confidence interval of the mean (Student t)${extra}.` : "";
    };

    // Sperling vs speed and peak vs speed: one panel per condition / group and direction
    const spCard = plotCard({ title: "Sperling index against speed", id: "plot-sperling-speed", description: "Sperling index against running speed: one panel per condition and direction, one colour per point", height: 520,
      csv: () => ({ header: ["group", "point", "direction", "speed (km/h)", "Sperling W (mean)", "95 % CI half width", "realisations", "section", "job"], rows: st.tables.sperling_vs_speed.flatMap((r) => r.speed_kmh.map((v, i) => [groupLabel(r.group), r.point, r.direction, v, r.value[i], r.ci95?.[i], r.n?.[i], r.sections?.[i], r.job_ids[i]])) }) });
    const pkCard = plotCard({ title: "Peak acceleration against speed", id: "plot-peak-speed", description: "Largest absolute acceleration against running speed with least-squares lines: one panel per condition and direction", height: 520,
      csv: () => ({ header: ["group", "point", "direction", "speed (km/h)", "peak (m/s², mean)", "95 % CI half width", "realisations", "section", "fit slope", "fit intercept", "R²", "job"], rows: st.tables.peak_vs_speed.flatMap((r) => r.speed_kmh.map((v, i) => [groupLabel(r.group), r.point, r.direction, v, r.value[i], r.ci95?.[i], r.n?.[i], r.sections?.[i], r.fit?.slope, r.fit?.intercept, r.fit?.r_squared, r.job_ids[i]])) }) });
    const frCard = plotCard({ title: "Flexible against rigid", id: "plot-flex-rigid", description: "Difference flexible − rigid in percent of rigid, per point and direction", height: 380,
      csv: () => ({ header: ["case", "speed (km/h)", "point", "direction", "quantity", "rigid", "flexible", "difference", "relative", "relative 95 % CI half width", "realisations", "section"], rows: (st.tables.flexible_vs_rigid || []).map((r) => [caseLabel(r), r.speed_kmh, r.point, r.direction, r.quantity, r.rigid, r.flexible, r.difference, r.relative, r.relative_ci95, r.n, r.section]) }) });
    const spControls = h("div", { class: "controls" });
    const pkControls = h("div", { class: "controls" });
    spCard.setControls(spControls);
    pkCard.setControls(pkControls);
    const fitTable = h("div");
    const frControls = h("div", { class: "controls" });
    const frTable = h("div");
    const jobsBox = h("div");

    function bindClicks(card) {
      if (card.bound || !card.plotEl.on) return;
      card.bound = true;
      card.plotEl.on("plotly_click", (ev) => {
        const jid = ev?.points?.[0]?.customdata;
        if (typeof jid === "string" && jid) go(`/jobs/${jid}`);
      });
    }

    function groupsOf(rows) {
      return [...new Map(rows.map((r) => [groupLabel(r.group), r.group])).keys()];
    }

    /** Positions and descriptions of the points: a finished job's recorded points (its
     * vehicle), else the paper's list (descriptions only). */
    async function refreshCatalogue() {
      const done = st.jobs.find((j) => j.status === "succeeded");
      if (!done || catalogueFrom === done.id) return;
      try {
        const ch = await cached(`channels:${done.id}`, () => api.channels(done.id));
        catalogueFrom = done.id;
        catalogue = pointCatalogue(ch.points);
        setChildren(pointsBox, pointsCard(catalogue, { id: "points-card", open: false, note: `Positions of the vehicle of job ${done.name}.` }));
      } catch { /* descriptions only */ }
    }

    function controls(el, rows, which) {
      const pts = pointsOf(rows);
      if (!state.points) state.points = pts.filter((p) => catalogue.get(p)?.kind !== "grid");
      const boxes = pts.map((p) => h("label", { class: "check" }, h("input", { type: "checkbox", value: p, checked: state.points.includes(p), onchange: (e) => {
        state.points = e.target.checked ? [...state.points, p] : state.points.filter((x) => x !== p);
        drawAll();
      } }), pointTag(p, catalogue)));
      setChildren(el,
        simpleSelect(`${which}-dir`, "Direction", [["both", "vertical and lateral"], ["z", "vertical (z)"], ["y", "lateral (y)"]], state.dir, (v) => { state.dir = v; sync(); drawAll(); }),
        h("fieldset", {}, h("legend", {}, "Points"), h("div", { class: "chips" }, boxes)));
    }

    function selected(rows) {
      return rows.filter((r) => dirs().includes(r.direction) && state.points.includes(r.point));
    }

    async function drawFacets(card, rows, opts) {
      const sel = selected(rows);
      if (!sel.length) {
        card.empty("Nothing to show for this choice: pick a point.");
        return sel;
      }
      const fig = facetFigure(sel, { groups: groupsOf(rows), dirs: dirs(), groupLabel, catalogue, order: pointsOf(rows), ...opts });
      card.plotEl.style.height = `${fig.height}px`;
      await card.draw(fig.data, fig.layout);
      bindClicks(card);
      return sel;
    }

    async function drawSperling() {
      const rows = st.tables.sperling_vs_speed || [];
      if (!rows.length) {
        setChildren(spControls);
        spCard.empty(st.counts.succeeded ? "No Sperling indices: they need at least 5 s of simulated time per job (see the notes)." : "The chart appears as the jobs finish.");
        return;
      }
      controls(spControls, rows, "sp");
      const sel = await drawFacets(spCard, rows, { yTitle: (d) => `W ${DIRECTION_NAMES[d]} (–)`, limits: [[2.5, "excellent < 2.5"], [2.75, "good < 2.75"], [3.0, "qualified ≤ 3.0"]], mode: "lines+markers" });
      if (sel.length) spCard.setNote(`One panel per condition${dirs().length > 1 ? " and direction" : ""} (${facetPanels(groupsOf(rows), dirs()).length} panels), one colour per point, the same in every chart. GB 5599 grades as dotted lines.${ciNote()} Click a point to open its job (the first realisation).`);
    }

    async function drawPeak() {
      const rows = st.tables.peak_vs_speed || [];
      if (!rows.length) {
        setChildren(pkControls);
        setChildren(fitTable);
        pkCard.empty("The chart appears as the jobs finish.");
        return;
      }
      controls(pkControls, rows, "pk");
      const sel = await drawFacets(pkCard, rows, { yTitle: (d) => `Peak |a| ${DIRECTION_NAMES[d]} (m/s²)`, withFit: true, mode: "markers", unit: "m/s²" });
      if (!sel.length) {
        setChildren(fitTable);
        return;
      }
      pkCard.setNote(`Least-squares lines dashed (R² in the table below and on hover).${ciNote()} Click a point to open its job.`);
      setChildren(fitTable, dataTable([
        { key: "group", label: "Group" }, { key: "point", label: "Point", format: (v) => pointTag(v, catalogue) },
        { key: "direction", label: "Direction", format: (v) => DIRECTION_NAMES[v] || v },
        { key: "slope", label: "Slope (m/s² per km/h)", num: true, format: (v) => fmt(v, 4) },
        { key: "intercept", label: "Intercept (m/s²)", num: true, format: (v) => fmt(v, 4) },
        { key: "r2", label: "R²", num: true, format: (v) => fixed(v, 4) },
        { key: "n", label: "Jobs", num: true },
      ], sel.map((r) => ({ group: groupLabel(r.group), point: r.point, direction: r.direction, slope: r.fit?.slope ?? null, intercept: r.fit?.intercept ?? null, r2: r.fit?.r_squared ?? null, n: r.fit?.n ?? r.value.filter((v) => v !== null).length })),
      { caption: "Linear fits of the peak acceleration against speed", className: "table-scroll" }));
    }

    const caseLabel = (r) => Object.entries(r.group || {}).filter(([k]) => k !== "speed_kmh").map(([, v]) => v).join(" · ") || "–";
    const caseKey = (r) => `${caseLabel(r)}${r.speed_kmh ? `, ${fmt(r.speed_kmh)} km/h` : ""}`;
    const QN = { sperling: "Sperling W (–)", a_w: "weighted rms a_w (m/s²)", rms: "rms (m/s²)", peak: "peak |a| (m/s²)" };

    async function drawFlexRigid() {
      const rows = st.tables.flexible_vs_rigid || [];
      const hasModels = (st.axes || []).some((a) => a.name === "body_model" && a.values.includes("rigid") && a.values.includes("flexible"));
      if (!rows.length) {
        setChildren(frControls);
        setChildren(frTable);
        frCard.empty(hasModels ? (ACTIVE.has(st.status) ? "The comparison appears when both the rigid and the flexible job of a case have finished." : "No pair of rigid and flexible jobs finished with results.") : "This study has no rigid-against-flexible axis. Create one with body models rigid and flexible (e.g. the Table 2 preset).");
        return;
      }
      const qs = [...new Set(rows.map((r) => r.quantity))];
      if (!qs.includes(state.frQ)) state.frQ = qs[0];
      const sel = rows.filter((r) => r.quantity === state.frQ);
      setChildren(frControls, simpleSelect("fr-quantity", "Quantity", qs.map((q) => [q, QN[q] || q]), state.frQ, (v) => { state.frQ = v; drawFlexRigid(); }));
      const fig = flexRigidFigure(sel, { caseLabel: caseKey, catalogue, order: pointsOf(sel), quantity: QN[state.frQ] || state.frQ });
      await frCard.draw(fig.data, fig.layout);
      frCard.setNote(`Bars: flexible − rigid in percent of rigid (the paper's Table 2); positive: the flexible body is the worse.${ciNote(" (the ratio realisation by realisation, on the same track)")} Hover for both values.`);
      setChildren(frTable, flexRigidTable(sel), flexRigidLinks(sel));
    }

    /** Paper Table 2: a row per case and point, vertical and lateral side by side. */
    function flexRigidTable(sel) {
      const cases = [...new Set(sel.map(caseKey))];
      const rows = [];
      for (const c of cases) {
        const of = sel.filter((r) => caseKey(r) === c);
        for (const point of pointsOf(of)) {
          const at = (d) => of.find((r) => r.point === point && r.direction === d) || {};
          const [z, y] = [at("z"), at("y")];
          const any = z.rigid_job ? z : y;
          rows.push({ case: c, point, rz: z.rigid, fz: z.flexible, dz: z.relative, cz: z.relative_ci95, ry: y.rigid, fy: y.flexible, dy: y.relative, cy: y.relative_ci95, rigid_job: any.rigid_job, flexible_job: any.flexible_job });
        }
      }
      const sign = (v) => Math.sign(Number((100 * (v ?? 0)).toFixed(1)));
      const diff = (v, ci) => h("span", { class: `nowrap ${sign(v) > 0 ? "pos" : sign(v) < 0 ? "neg" : ""}` }, pct(v), ci == null ? "" : ` ± ${fixed(100 * ci, 1)}`);
      const dirCols = (k) => [
        { key: `r${k}`, label: "Rigid", num: true, sep: true, format: (v) => fmt(v, 3) },
        { key: `f${k}`, label: "Flexible", num: true, format: (v) => fmt(v, 3) },
        { key: `d${k}`, label: "Δ (%)", num: true, title: "flexible − rigid, in percent of rigid (± the 95 % confidence interval over the realisations)", format: (v, r) => diff(v, r[`c${k}`]) },
      ];
      const many = cases.length > 1;
      return dataTable([
        ...(many ? [{ key: "case", label: "Case" }] : []),
        { key: "point", label: "Point", format: (v) => pointTag(v, catalogue) },
        ...dirCols("z"), ...dirCols("y"),
      ], rows, {
        caption: `Flexible against rigid car body and frames (paper Table 2): ${QN[state.frQ] || state.frQ}${many ? "" : `, ${cases[0]}`}`,
        className: "table-scroll", groups: [{ label: "", span: many ? 2 : 1 }, { label: "Vertical (z)", span: 3 }, { label: "Lateral (y)", span: 3 }],
      });
    }

    /** The jobs of each case: rigid, flexible and their overlay (differences against rigid). */
    function flexRigidLinks(sel) {
      const cases = [...new Map(sel.map((r) => [caseKey(r), r])).values()];
      const centre = paperPoints().find((p) => p.along === "centre" && p.level === "floor")?.name || sel[0].point;
      return h("ul", { class: "small plain-list", id: "flex-rigid-jobs" }, cases.map((r) => h("li", {}, `${caseKey(r)}: `,
        h("a", { href: `#/jobs/${r.rigid_job}` }, "rigid job"), " · ", h("a", { href: `#/jobs/${r.flexible_job}` }, "flexible job"), " · ",
        h("a", { href: `#/compare?jobs=${r.rigid_job},${r.flexible_job}&ref=${r.rigid_job}&channel=carbody.${centre}.acc.z` }, "overlay (differences against rigid)"))));
    }

    /** Where each index is evaluated: the section per group and speed (the same for every
     * point and direction of a group). */
    function sectionsCard(rows) {
      const seen = new Map();
      for (const r of rows) {
        (r.sections || []).forEach((sec, i) => {
          const key = `${groupLabel(r.group)}|${r.speed_kmh[i]}`;
          if (!seen.has(key)) seen.set(key, { group: groupLabel(r.group), speed: r.speed_kmh[i], section: sec });
        });
      }
      if (!seen.size) return null;
      return h("details", { class: "card", id: "study-sections" }, h("summary", {}, "Evaluated sections (where every index of the tables and charts is taken)"),
        dataTable([{ key: "group", label: "Group" }, { key: "speed", label: "Speed (km/h)", num: true }, { key: "section", label: "Section (vehicle centre along the line)" }],
          [...seen.values()], { caption: "Each job's indices are those of this section of its run", className: "table-scroll" }));
    }

    function drawJobs() {
      const sp = st.tables.sperling_vs_speed || [];
      const pk = st.tables.peak_vs_speed || [];
      const allPts = pointsOf([...sp, ...pk]);
      if (!allPts.includes(state.tablePoint)) state.tablePoint = allPts[0] || "";
      const val = (rows, jid, p, d) => {
        const r = rows.find((x) => x.point === p && x.direction === d && (x.job_values ? jid in x.job_values : x.job_ids.includes(jid)));
        if (!r) return null;
        return r.job_values ? r.job_values[jid] : r.value[r.job_ids.indexOf(jid)];
      };
      const axisNames = (st.axes || []).map((a) => a.name);
      const p = state.tablePoint;
      const cols = [
        { key: "index", label: "#", num: true },
        { key: "name", label: "Job", format: (v, r) => h("a", { href: `#/jobs/${r.id}` }, v) },
        ...axisNames.map((a) => ({ key: `ax:${a}`, label: a.replace(/_kmh$/, " (km/h)").replace(/_/g, " "), value: (r) => r.axes[a], format: (v) => (typeof v === "number" ? fmt(v) : String(v ?? "–")) })),
        { key: "status", label: "Status", format: (v, r) => h("span", {}, badge(v), r.error ? h("div", { class: "error-text" }, r.error) : null) },
        { key: "wz", label: `W vertical ${p}`, title: pointText(p, catalogue), num: true, format: (v) => fixed(v) },
        { key: "wy", label: `W lateral ${p}`, num: true, format: (v) => fixed(v) },
        { key: "pz", label: `Peak vertical ${p} (m/s²)`, num: true, format: (v) => fmt(v, 3) },
        { key: "py", label: `Peak lateral ${p} (m/s²)`, num: true, format: (v) => fmt(v, 3) },
      ];
      const rows = st.jobs.map((j) => ({ ...j, wz: val(sp, j.id, p, "z"), wy: val(sp, j.id, p, "y"), pz: val(pk, j.id, p, "z"), py: val(pk, j.id, p, "y") }));
      setChildren(jobsBox,
        allPts.length ? h("div", { class: "controls" }, simpleSelect("jobs-point", "Point", allPts.map((x) => [x, pointText(x, catalogue)]), p, (v) => { state.tablePoint = v; drawJobs(); })) : null,
        dataTable(cols, rows, { caption: "Every job of the study with its indices (Enter or click opens a job)", onRow: (r) => go(`/jobs/${r.id}`), rowLabel: (r) => `Open job ${r.name}`, className: "table-scroll" }));
    }

    async function drawAll() {
      await Promise.all([drawSperling(), drawPeak(), drawFlexRigid()]);
      drawJobs();
    }

    const t = tabs([
      { id: "sperling", label: "Sperling vs speed" },
      { id: "peak", label: "Peak vs speed" },
      { id: "flexrigid", label: "Flexible vs rigid" },
      { id: "jobs", label: "Jobs and indices" },
    ], (tab, panel) => {
      if (tab === "sperling") panel.append(spCard.el);
      if (tab === "peak") panel.append(pkCard.el, h("section", { class: "card" }, fitTable));
      if (tab === "flexrigid") panel.append(h("div", { class: "grid2 flex-rigid" }, frCard.el, h("section", { class: "card" }, frControls, frTable)));
      if (tab === "jobs") panel.append(h("section", { class: "card" }, jobsBox));
    }, { label: "Study results", initial: ctx.query.tab || "sperling" });
    t.onSelect = (tab) => {
      state.tab = tab;
      sync();
    };
    state.tab = ctx.query.tab || "sperling";
    setChildren(pointsBox, pointsCard(catalogue, { id: "points-card", open: false, note: "Positions appear when a job of the study has finished." }));
    setChildren(body, notesEl, meshEl, sectionsEl, pointsBox, t.el);
    return {
      async update(next) {
        st = next;
        const notes = st.tables.notes || [];
        setChildren(notesEl, notes.length ? notice("info", null, h("ul", {}, notes.map((n) => h("li", {}, n)))) : null);
        setChildren(sectionsEl, sectionsCard(st.tables.sperling_vs_speed?.length ? st.tables.sperling_vs_speed : st.tables.peak_vs_speed || []));
        const meshTables = st.tables.mesh_convergence || [];
        if (meshTables.length) {
          if (!mesh) mesh = meshSection();
          if (!mesh.el.isConnected) setChildren(meshEl, mesh.el);
          mesh.update(meshTables).catch((e) => console.warn(e));
        } else setChildren(meshEl);
        await refreshCatalogue();
        drawAll().catch((e) => console.warn(e));
      },
    };
  }

  await poll();
  return () => clearTimeout(timer);
}
