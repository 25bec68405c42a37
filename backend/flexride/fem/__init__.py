"""Finite-element models of the car body and bogie frame, eigen solutions and reductions.

Public entry points:

* :func:`flexride.fem.flexible.build_flexible_body` — a reduced flexible body
  (:class:`~flexride.fem.flexible_body.FlexibleBody`) for the solver, cached on disk
  (:mod:`flexride.fem.body_cache`); :func:`~flexride.fem.flexible.flexible_body_from_model`
  the same for any FE model;
* :func:`flexride.fem.modal_body.reduced_to_modal_body` — any (reduced) M, K to a ModalBody;
* :func:`flexride.fem.carbody.build_carbody`, :func:`flexride.fem.frame.build_frame` — the
  parametric FE models; :func:`flexride.fem.vehicle_models.build_fe_model` — those of a
  vehicle, mass-matched to its parameters;
* :mod:`flexride.fem.reduction` — Guyan, Craig–Bampton and modal truncation;
  :func:`flexride.fem.reduce.reduce_model` — one of them applied to a model, with its report;
* :mod:`flexride.fem.export` — mesh and mode shapes for the browser (``flexride fe export``,
  the service's exports);
* :mod:`flexride.fem.importers` — external M and K (MatrixMarket, ANSYS HBMAT and .full, Nastran
  DMIG and OP4);
* :mod:`flexride.fem.calibration` — model updating against targets
  (:class:`~flexride.fem.targets.ModeTarget`: frequency, mode type of
  :mod:`~flexride.fem.mode_types`, reference shape), paired with model modes by
  :mod:`~flexride.fem.pairing` (type, MAC of :mod:`~flexride.fem.mac`, frequency);
  measured modes from :mod:`flexride.fem.modal_test`.

pyfe3d is used only inside :mod:`flexride.fem.pyfe3d_adapter`. Nothing here is imported by
``import flexride``; import the submodules you need.
"""
