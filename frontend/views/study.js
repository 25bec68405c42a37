// Study result: Sperling against speed per condition and point (paper Figs. 14, 17, 22), peak
// acceleration against speed with the fitted line and R² (Fig. 21), flexible against rigid with
// differences in percent (Table 2) and every job's indices; clicking a point opens its job.

import { api, cached } from "../api.js";
import { h, setChildren, badge, progressBar, fmt, fixed, pct, errorBox, notice, loading, tabs, dataTable, when, DIRECTION_NAMES } from "../components/dom.js";
import { plotCard, baseLayout, COLORS, DASHES, loadPlotly } from "../components/plot.js";
import { simpleSelect, directionOptions } from "../components/channels.js";
import { confirmButton } from "./jobs.js";
import { go, replaceQuery } from "../components/nav.js";

/** The paper's points in their order (GET /schemas/points), loaded with the study. */
let paperPoints = [];
let paperOrder = [];
const SYMBOLS = ["circle", "square", "diamond", "triangle-up", "cross", "x", "star", "triangle-down"];
const ACTIVE = new Set(["queued", "running"]);
const SIDE_LEGEND = { orientation: "v", x: 1.02, xanchor: "left", y: 1, yanchor: "top", font: { size: 11 } };

export const groupLabel = (g) => Object.entries(g || {}).map(([k, v]) => (k === "body_model" ? `${v} body` : String(v))).join(" · ") || "all jobs";

function pointsOf(rows) {
  const pts = [...new Set(rows.map((r) => r.point))];
  return [...paperOrder.filter((p) => pts.includes(p)), ...pts.filter((p) => !paperOrder.includes(p)).sort()];
}

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
      if (!paperOrder.length) {
        paperPoints = await cached("paper-points", api.paperPoints);
        paperOrder = paperPoints.map((p) => p.name);
      }
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
    if (!view) view = buildView(st);
    if (key !== lastKey) {
      lastKey = key;
      view.update(st);
    }
    if (ACTIVE.has(st.status)) timer = setTimeout(poll, 1500);
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
        h("div", { class: "grow" }, progressBar(st.progress, "Study progress", st.status)),
        h("span", { id: "study-counts" }, `${st.n_jobs} jobs: ${Object.entries(st.counts).map(([k, v]) => `${v} ${k}`).join(", ") || "none"}`)),
      h("p", { class: "small muted" }, axes.join(" · "), ` · created ${when(st.created_at)}`)));
  }

  function buildView(st0) {
    const notesEl = h("div");
    const state = { dir: ctx.query.dir || "z", group: ctx.query.group ?? "", points: null, peakPoint: "" , frQ: "sperling", tablePoint: "" };
    let st = st0;
    const sync = () => replaceQuery({ tab: state.tab, dir: state.dir, group: state.group });

    // Sperling vs speed
    const spCard = plotCard({ title: "Sperling index against speed", id: "plot-sperling-speed", description: "Sperling index against running speed per condition and point", height: 420,
      csv: () => ({ header: ["group", "point", "direction", "speed (km/h)", "Sperling W", "job"], rows: st.tables.sperling_vs_speed.flatMap((r) => r.speed_kmh.map((v, i) => [groupLabel(r.group), r.point, r.direction, v, r.value[i], r.job_ids[i]])) }) });
    const pkCard = plotCard({ title: "Peak acceleration against speed", id: "plot-peak-speed", description: "Largest absolute acceleration against running speed with least-squares lines", height: 420,
      csv: () => ({ header: ["group", "point", "direction", "speed (km/h)", "peak (m/s²)", "fit slope", "fit intercept", "R²", "job"], rows: st.tables.peak_vs_speed.flatMap((r) => r.speed_kmh.map((v, i) => [groupLabel(r.group), r.point, r.direction, v, r.value[i], r.fit?.slope, r.fit?.intercept, r.fit?.r_squared, r.job_ids[i]])) }) });
    const spControls = h("div", { class: "controls" });
    const pkControls = h("div", { class: "controls" });
    spCard.setControls(spControls);
    pkCard.setControls(pkControls);
    const fitTable = h("div");
    const frBox = h("div");
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

    function controls(el, rows, which) {
      const groups = groupsOf(rows);
      const pts = pointsOf(rows);
      const centre = paperPoints.find((p) => p.along === "centre" && p.level === "floor")?.name;
      if (!state.points) state.points = pts.includes(centre) && groups.length > 1 ? [centre] : pts.slice();
      if (state.group && !groups.includes(state.group)) state.group = "";
      const boxes = pts.map((p) => h("label", { class: "check" }, h("input", { type: "checkbox", value: p, checked: state.points.includes(p), onchange: (e) => {
        state.points = e.target.checked ? [...state.points, p] : state.points.filter((x) => x !== p);
        drawAll();
      } }), p));
      setChildren(el,
        simpleSelect(`${which}-dir`, "Direction", directionOptions(["z", "y"]), state.dir, (v) => { state.dir = v; sync(); drawAll(); }),
        simpleSelect(`${which}-group`, "Condition / group", [["", `all (${groups.length})`], ...groups.map((g) => [g, g])], state.group, (v) => { state.group = v; sync(); drawAll(); }),
        h("fieldset", {}, h("legend", {}, "Points"), h("div", { class: "chips" }, boxes)));
    }

    function speedTraces(rows, withFit) {
      const sel = rows.filter((r) => r.direction === state.dir && state.points.includes(r.point) && (!state.group || groupLabel(r.group) === state.group));
      const groups = groupsOf(rows);
      const pts = pointsOf(rows);
      const traces = [];
      const ann = [];
      for (const r of sel) {
        const gi = groups.indexOf(groupLabel(r.group));
        const color = COLORS[pts.indexOf(r.point) % COLORS.length];
        const name = `${r.point}${groups.length > 1 ? ` · ${groupLabel(r.group)}` : ""}`;
        const fitOk = withFit && r.fit && r.fit.slope !== null;
        traces.push({
          type: "scatter", mode: withFit ? "markers" : "lines+markers", name: fitOk ? `${name} (R² = ${fixed(r.fit.r_squared, 3)})` : name, x: r.speed_kmh, y: r.value, customdata: r.job_ids,
          legendgroup: name, marker: { color, size: 8, symbol: SYMBOLS[gi % SYMBOLS.length] }, line: { color, dash: DASHES[gi % DASHES.length], width: 1.6 },
          hovertemplate: `${name}<br>%{x} km/h: %{y:.3f}${withFit ? " m/s²" : ""}<br>click to open the job<extra></extra>`,
        });
        if (fitOk) {
          const x0 = Math.min(...r.speed_kmh);
          const x1 = Math.max(...r.speed_kmh);
          traces.push({
            type: "scatter", mode: "lines", name: `fit ${name}: R² = ${fixed(r.fit.r_squared, 3)}`, legendgroup: name, showlegend: false, hoverinfo: "skip",
            x: [x0, x1], y: [r.fit.slope * x0 + r.fit.intercept, r.fit.slope * x1 + r.fit.intercept], line: { color, dash: "dash", width: 1.2 },
          });
        }
      }
      return { traces, ann, sel };
    }

    async function drawSperling() {
      const rows = st.tables.sperling_vs_speed || [];
      if (!rows.length) {
        setChildren(spControls);
        spCard.empty(st.counts.succeeded ? "No Sperling indices: they need at least 5 s of simulated time per job (see the notes)." : "The chart appears as the jobs finish.");
        return;
      }
      controls(spControls, rows, "sp");
      const { traces } = speedTraces(rows, false);
      if (!traces.length) {
        spCard.empty("Nothing to show for this choice: pick a point or a group.");
        return;
      }
      const speeds = rows.flatMap((r) => r.speed_kmh);
      const x0 = Math.min(...speeds) - 3;
      const x1 = Math.max(...speeds) + 3;
      const limits = [[2.5, "excellent < 2.5"], [2.75, "good < 2.75"], [3.0, "qualified ≤ 3.0"]];
      await spCard.draw(traces, baseLayout("Speed (km/h)", `Sperling index W ${DIRECTION_NAMES[state.dir]} (–)`, {
        hovermode: "closest", xaxis: { range: [x0, x1] }, legend: SIDE_LEGEND,
        shapes: limits.map(([y]) => ({ type: "line", xref: "paper", x0: 0, x1: 1, y0: y, y1: y, line: { color: "#9aa3ad", dash: "dot", width: 1 } })),
        annotations: limits.map(([y, t]) => ({ xref: "paper", x: 1, y, text: t, showarrow: false, xanchor: "right", yanchor: "bottom", font: { size: 10, color: "#52606d" } })),
      }));
      bindClicks(spCard);
      spCard.setNote("GB 5599 grades as dotted lines. Click a point to open its job.");
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
      const { traces, sel } = speedTraces(rows, true);
      if (!traces.length) {
        pkCard.empty("Nothing to show for this choice: pick a point or a group.");
        setChildren(fitTable);
        return;
      }
      await pkCard.draw(traces, baseLayout("Speed (km/h)", `Peak |acceleration| ${DIRECTION_NAMES[state.dir]} (m/s²)`, { hovermode: "closest", legend: SIDE_LEGEND }));
      bindClicks(pkCard);
      pkCard.setNote("Least-squares lines dashed, R² in the legend. Click a point to open its job.");
      setChildren(fitTable, dataTable([
        { key: "group", label: "Group" }, { key: "point", label: "Point" },
        { key: "slope", label: "Slope (m/s² per km/h)", num: true, format: (v) => fmt(v, 4) },
        { key: "intercept", label: "Intercept (m/s²)", num: true, format: (v) => fmt(v, 4) },
        { key: "r2", label: "R²", num: true, format: (v) => fixed(v, 4) },
        { key: "n", label: "Jobs", num: true },
      ], sel.map((r) => ({ group: groupLabel(r.group), point: r.point, slope: r.fit?.slope ?? null, intercept: r.fit?.intercept ?? null, r2: r.fit?.r_squared ?? null, n: r.fit?.n ?? r.value.filter((v) => v !== null).length })),
      { caption: `Linear fits of the peak ${DIRECTION_NAMES[state.dir]} acceleration against speed` }));
    }

    function drawFlexRigid() {
      const rows = st.tables.flexible_vs_rigid || [];
      const hasModels = (st.axes || []).some((a) => a.name === "body_model" && a.values.includes("rigid") && a.values.includes("flexible"));
      if (!rows.length) {
        setChildren(frBox, notice("empty", null, hasModels ? (ACTIVE.has(st.status) ? "The comparison appears when both the rigid and the flexible job of a case have finished." : "No pair of rigid and flexible jobs finished with results.") : "This study has no rigid-against-flexible axis. Create one with body models rigid and flexible (e.g. the Table 2 preset)."));
        return;
      }
      const qs = [...new Set(rows.map((r) => r.quantity))];
      if (!qs.includes(state.frQ)) state.frQ = qs[0];
      const QN = { sperling: "Sperling W (–)", a_w: "weighted rms a_w (m/s²)", rms: "rms (m/s²)", peak: "peak |a| (m/s²)" };
      const sel = rows.filter((r) => state.frQ === "all" || r.quantity === state.frQ);
      setChildren(frBox,
        h("div", { class: "controls" }, simpleSelect("fr-quantity", "Quantity", [...qs.map((q) => [q, QN[q] || q]), ["all", "all"]], state.frQ, (v) => { state.frQ = v; drawFlexRigid(); })),
        dataTable([
          { key: "group", label: "Case" },
          { key: "speed_kmh", label: "Speed (km/h)", num: true },
          { key: "point", label: "Point" },
          { key: "direction", label: "Direction", format: (v) => DIRECTION_NAMES[v] || v },
          { key: "quantity", label: "Quantity", format: (v) => QN[v] || v },
          { key: "rigid", label: "Rigid", num: true, format: (v) => fmt(v, 3) },
          { key: "flexible", label: "Flexible", num: true, format: (v) => fmt(v, 3) },
          { key: "difference", label: "Difference", num: true, format: (v) => fmt(v, 3) },
          { key: "relative", label: "Difference (%)", num: true, format: (v) => h("span", { class: v > 0 ? "pos" : v < 0 ? "neg" : "" }, pct(v)) },
          { key: "links", label: "Jobs", value: () => null, format: (v, r) => h("span", {}, h("a", { href: `#/jobs/${r.rigid_job}` }, "rigid"), " · ", h("a", { href: `#/jobs/${r.flexible_job}` }, "flexible"), " · ", h("a", { href: `#/compare?jobs=${r.rigid_job},${r.flexible_job}&channel=carbody.${r.point}.acc.${r.direction}` }, "overlay")) },
        ], sel.map((r) => ({ ...r, group: Object.entries(r.group).filter(([k]) => k !== "speed_kmh").map(([, v]) => v).join(" · ") || "–" })),
        { caption: "Flexible against rigid car body and frames (paper Table 2): difference = flexible − rigid, in percent of rigid", className: "table-scroll" }));
    }

    function drawJobs() {
      const sp = st.tables.sperling_vs_speed || [];
      const pk = st.tables.peak_vs_speed || [];
      const allPts = pointsOf([...sp, ...pk]);
      if (!allPts.includes(state.tablePoint)) state.tablePoint = allPts[0] || "";
      const val = (rows, jid, p, d) => {
        const r = rows.find((x) => x.point === p && x.direction === d && x.job_ids.includes(jid));
        return r ? r.value[r.job_ids.indexOf(jid)] : null;
      };
      const axisNames = (st.axes || []).map((a) => a.name);
      const p = state.tablePoint;
      const cols = [
        { key: "index", label: "#", num: true },
        { key: "name", label: "Job", format: (v, r) => h("a", { href: `#/jobs/${r.id}` }, v) },
        ...axisNames.map((a) => ({ key: `ax:${a}`, label: a.replace(/_kmh$/, " (km/h)").replace(/_/g, " "), value: (r) => r.axes[a], format: (v) => (typeof v === "number" ? fmt(v) : String(v ?? "–")) })),
        { key: "status", label: "Status", format: (v, r) => h("span", {}, badge(v), r.error ? h("div", { class: "error-text" }, r.error) : null) },
        { key: "wz", label: `W vertical ${p}`, num: true, format: (v) => fixed(v) },
        { key: "wy", label: `W lateral ${p}`, num: true, format: (v) => fixed(v) },
        { key: "pz", label: `Peak vertical ${p} (m/s²)`, num: true, format: (v) => fmt(v, 3) },
        { key: "py", label: `Peak lateral ${p} (m/s²)`, num: true, format: (v) => fmt(v, 3) },
      ];
      const rows = st.jobs.map((j) => ({ ...j, wz: val(sp, j.id, p, "z"), wy: val(sp, j.id, p, "y"), pz: val(pk, j.id, p, "z"), py: val(pk, j.id, p, "y") }));
      setChildren(jobsBox,
        allPts.length ? h("div", { class: "controls" }, simpleSelect("jobs-point", "Point", allPts.map((x) => [x, x]), p, (v) => { state.tablePoint = v; drawJobs(); })) : null,
        dataTable(cols, rows, { caption: "Every job of the study with its indices (Enter or click opens a job)", onRow: (r) => go(`/jobs/${r.id}`), rowLabel: (r) => `Open job ${r.name}`, className: "table-scroll" }));
    }

    async function drawAll() {
      await Promise.all([drawSperling(), drawPeak()]);
      drawFlexRigid();
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
      if (tab === "flexrigid") panel.append(h("section", { class: "card" }, frBox));
      if (tab === "jobs") panel.append(h("section", { class: "card" }, jobsBox));
    }, { label: "Study results", initial: ctx.query.tab || "sperling" });
    t.onSelect = (tab) => {
      state.tab = tab;
      sync();
    };
    state.tab = ctx.query.tab || "sperling";
    setChildren(body, notesEl, t.el);
    return {
      update(next) {
        st = next;
        const notes = st.tables.notes || [];
        setChildren(notesEl, notes.length ? notice("info", null, h("ul", {}, notes.map((n) => h("li", {}, n)))) : null);
        drawAll().catch((e) => console.warn(e));
      },
    };
  }

  await poll();
  return () => clearTimeout(timer);
}
