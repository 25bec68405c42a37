// Jobs and studies: status, live progress (polling), duration, cancel, delete, filter, paging.

import { api } from "../api.js";
import { h, setChildren, badge, progressBar, duration, when, fmt, errorBox, notice, loading, tabs } from "../components/dom.js";
import { replaceQuery, go } from "../components/nav.js";

const ACTIVE = new Set(["queued", "running"]);
const PAGE = 50;

/** The status a study's progress bar shows: running while any of its jobs is queued or running
 * (so it reads 100 % only when every job has finished). */
export function studyBarStatus(st) {
  const open = (st.counts?.queued || 0) + (st.counts?.running || 0);
  return open > 0 ? "running" : st.status;
}

/** A delete button that asks once more before acting (no modal dialog). */
export function confirmButton(label, confirmLabel, action, { danger = true } = {}) {
  let armed = false;
  let timer = null;
  const b = h("button", { type: "button", class: `btn btn-small${danger ? " btn-danger" : ""}` }, label);
  b.addEventListener("click", async () => {
    if (!armed) {
      armed = true;
      b.textContent = confirmLabel;
      b.classList.add("confirm");
      timer = setTimeout(() => {
        armed = false;
        b.textContent = label;
        b.classList.remove("confirm");
      }, 5000);
      return;
    }
    clearTimeout(timer);
    b.disabled = true;
    try {
      await action();
    } finally {
      b.disabled = false;
      armed = false;
      b.textContent = label;
      b.classList.remove("confirm");
    }
  });
  return b;
}

export default async function render(main, ctx) {
  ctx.title("Jobs and studies");
  const q = ctx.query;
  const state = {
    tab: q.tab === "studies" ? "studies" : "jobs",
    status: q.status || "",
    study: q.study || "",
    text: q.q || "",
    offset: Number(q.offset) || 0,
    soffset: 0,
    selected: new Set(),
  };
  const msg = h("div", { "aria-live": "polite" });
  const sync = () => replaceQuery({ tab: state.tab === "studies" ? "studies" : "", status: state.status, study: state.study, q: state.text, offset: state.offset || "" });

  main.append(
    h("div", { class: "page-head" }, h("h1", {}, "Jobs and studies"),
      h("div", { class: "actions" },
        h("a", { class: "btn btn-primary", href: "#/new" }, "New job"),
        h("a", { class: "btn", href: "#/studies/new" }, "New study"))),
    msg);

  // -- jobs ------------------------------------------------------------------------------------
  const jobRows = new Map();
  const jobsBody = h("tbody");
  const jobsInfo = h("span", { class: "muted", id: "jobs-count", "aria-live": "polite" });
  const prev = h("button", { type: "button", class: "btn btn-small", onclick: () => { state.offset = Math.max(0, state.offset - PAGE); sync(); refreshJobs(true); } }, "← Newer");
  const next = h("button", { type: "button", class: "btn btn-small", onclick: () => { state.offset += PAGE; sync(); refreshJobs(true); } }, "Older →");
  const compareBtn = h("button", { type: "button", class: "btn btn-small", disabled: true, onclick: () => go(`/compare?jobs=${[...state.selected].join(",")}`) }, "Compare selected");
  const statusSel = h("select", { id: "filter-status", onchange: () => { state.status = statusSel.value; state.offset = 0; sync(); refreshJobs(true); } },
    ["", "queued", "running", "succeeded", "failed", "cancelled"].map((s) => h("option", { value: s, selected: s === state.status }, s || "any")));
  const studySel = h("select", { id: "filter-study", onchange: () => { state.study = studySel.value; state.offset = 0; sync(); refreshJobs(true); } },
    h("option", { value: "" }, "any"));
  const textIn = h("input", { id: "filter-text", type: "search", value: state.text, placeholder: "name or id", oninput: () => { state.text = textIn.value; sync(); applyText(); } });
  const jobsTable = h("div", { class: "table-wrap" }, h("table", { class: "data", id: "jobs-table" },
    h("caption", { class: "sr-only" }, "Jobs, newest first"),
    h("thead", {}, h("tr", {},
      h("th", { scope: "col" }, h("span", { class: "sr-only" }, "Select for comparison")),
      h("th", { scope: "col" }, "Name"), h("th", { scope: "col" }, "Status"), h("th", { scope: "col" }, "Progress"),
      h("th", { scope: "col", class: "num" }, "Speed (km/h)"), h("th", { scope: "col", class: "num" }, "Simulated (s)"),
      h("th", { scope: "col" }, "Created"), h("th", { scope: "col", class: "num" }, "Run time"),
      h("th", { scope: "col" }, h("span", { class: "sr-only" }, "Actions")))),
    jobsBody));
  const jobsEmpty = h("div");

  let lastPage = { total: 0, n: 0 };
  const noMatch = h("div");

  /** Hide the rows the name filter excludes; the pager counts what is shown. */
  function applyText() {
    const t = state.text.trim().toLowerCase();
    let shown = 0;
    for (const [id, r] of jobRows) {
      r.tr.hidden = !!t && !(r.job.name.toLowerCase().includes(t) || id.includes(t));
      if (!r.tr.hidden) shown += 1;
    }
    const { total, n } = lastPage;
    const range = total ? `${state.offset + 1}–${state.offset + n} of ${total}` : "";
    jobsInfo.textContent = t && total ? `${shown} of ${n} on this page match “${state.text.trim()}” (jobs ${range})` : range;
    setChildren(noMatch, t && n && !shown ? notice("empty", null, `No job on this page matches “${state.text.trim()}”.`) : null);
  }

  function jobActions(job) {
    const out = [h("a", { class: "btn btn-small", href: `#/jobs/${job.id}` }, job.status === "succeeded" ? "Results" : "Open")];
    if (ACTIVE.has(job.status)) {
      out.push(h("button", { type: "button", class: "btn btn-small", onclick: async (e) => {
        e.target.disabled = true;
        try {
          await api.cancelJob(job.id);
          refreshJobs();
        } catch (err) {
          setChildren(msg, errorBox(err, "Could not cancel the job"));
          e.target.disabled = false;
        }
      } }, "Cancel"));
    }
    out.push(confirmButton("Delete", "Confirm delete", async () => {
      try {
        await api.deleteJob(job.id);
        setChildren(msg, notice("info", null, `Deleted job ${job.name}.`));
        refreshJobs(true);
      } catch (err) {
        setChildren(msg, errorBox(err, "Could not delete the job"));
      }
    }));
    return h("div", { class: "row-actions" }, out);
  }

  function jobRow(job) {
    const check = h("input", { type: "checkbox", "aria-label": `Select ${job.name} for comparison`, disabled: !job.has_results, checked: state.selected.has(job.id), onchange: () => {
      if (check.checked) state.selected.add(job.id);
      else state.selected.delete(job.id);
      compareBtn.disabled = state.selected.size < 2;
      compareBtn.textContent = `Compare selected (${state.selected.size})`;
    } });
    const cells = {
      name: h("th", { scope: "row" }),
      status: h("td"), progress: h("td"), speed: h("td", { class: "num" }), dur: h("td", { class: "num" }),
      created: h("td"), run: h("td", { class: "num" }), actions: h("td"),
    };
    const tr = h("tr", { dataset: { id: job.id } }, h("td", {}, check), Object.values(cells));
    return { tr, cells, check, job: null, lastStatus: null };
  }

  function updateRow(r, job) {
    r.job = job;
    const c = r.cells;
    setChildren(c.name, h("a", { href: `#/jobs/${job.id}` }, job.name),
      job.study_id ? h("div", { class: "small muted" }, "study ", h("a", { href: `#/studies/${job.study_id}` }, job.study_id.slice(0, 8))) : null,
      job.reused_from ? h("div", { class: "small muted" }, "results reused") : null);
    setChildren(c.status, badge(job.status));
    setChildren(c.progress, progressBar(job.progress, `Progress of ${job.name}`, job.status),
      job.status === "failed" ? h("div", { class: "error-text" }, job.error || job.message) :
        h("div", { class: "small muted" }, job.message));
    c.speed.textContent = fmt(job.speed_kmh);
    c.dur.textContent = fmt(job.duration_s);
    c.created.textContent = when(job.created_at);
    c.run.textContent = duration(job.run_time_s);
    r.check.disabled = !job.has_results;
    if (r.lastStatus !== job.status) {
      r.lastStatus = job.status;
      setChildren(c.actions, jobActions(job));
    }
  }

  let jobsTimer = null;
  let jobsCtrl = null;
  async function refreshJobs(reset = false) {
    clearTimeout(jobsTimer);
    if (ctx.signal.aborted) return;
    jobsCtrl?.abort();
    jobsCtrl = new AbortController();
    let page;
    try {
      page = await api.jobs({ status: state.status || undefined, study_id: state.study || undefined, limit: PAGE, offset: state.offset }, { signal: jobsCtrl.signal });
    } catch (err) {
      if (ctx.signal.aborted || err.name === "AbortError") return;
      setChildren(jobsEmpty, errorBox(err, "Could not load the jobs"));
      jobsTimer = setTimeout(refreshJobs, 5000);
      return;
    }
    if (reset) {
      jobRows.clear();
      jobsBody.replaceChildren();
    }
    const seen = new Set();
    page.items.forEach((job, i) => {
      seen.add(job.id);
      let r = jobRows.get(job.id);
      if (!r) {
        r = jobRow(job);
        jobRows.set(job.id, r);
      }
      updateRow(r, job);
      if (jobsBody.children[i] !== r.tr) jobsBody.insertBefore(r.tr, jobsBody.children[i] || null);
    });
    for (const [id, r] of jobRows) {
      if (!seen.has(id)) {
        r.tr.remove();
        jobRows.delete(id);
      }
    }
    lastPage = { total: page.total, n: page.items.length };
    applyText();
    jobsTable.hidden = page.items.length === 0;
    setChildren(jobsEmpty, page.items.length ? null : notice("empty", "No jobs here yet",
      state.status || state.study ? "No job matches these filters." : h("span", {}, "Submit one from ", h("a", { href: "#/new" }, "New job"), " or run a ", h("a", { href: "#/studies/new" }, "study"), ".")));
    prev.disabled = state.offset === 0;
    next.disabled = state.offset + page.items.length >= page.total;
    const active = page.items.some((j) => ACTIVE.has(j.status));
    if (!ctx.signal.aborted) jobsTimer = setTimeout(refreshJobs, document.hidden ? 10000 : active ? 1000 : 5000);
  }

  // -- studies ---------------------------------------------------------------------------------
  const studyRows = new Map();
  const studiesBody = h("tbody");
  const studiesEmpty = h("div", {}, loading("Loading studies…"));
  const studiesTable = h("div", { class: "table-wrap", hidden: true }, h("table", { class: "data", id: "studies-table" },
    h("caption", { class: "sr-only" }, "Studies, newest first"),
    h("thead", {}, h("tr", {}, ["Name", "Status", "Progress", "Jobs", "Created", ""].map((t, i) => h("th", { scope: "col", class: i === 3 ? "num" : "" }, t || h("span", { class: "sr-only" }, "Actions"))))),
    studiesBody));
  const studiesBox = h("div", {}, studiesEmpty, studiesTable);

  function studyActions(s) {
    return h("div", { class: "row-actions" },
      h("a", { class: "btn btn-small", href: `#/studies/${s.id}` }, "Results"),
      h("a", { class: "btn btn-small", href: `#/?study=${s.id}`, onclick: (e) => { e.preventDefault(); state.study = s.id; state.offset = 0; t.select("jobs", true); studySel.value = s.id; sync(); refreshJobs(true); } }, "Jobs"),
      ACTIVE.has(s.status) ? h("button", { type: "button", class: "btn btn-small", onclick: async (e) => {
        e.target.disabled = true;
        try {
          await api.cancelStudy(s.id);
          refreshStudies();
        } catch (err) {
          setChildren(msg, errorBox(err, "Could not cancel the study"));
          e.target.disabled = false;
        }
      } }, "Cancel") : null,
      confirmButton("Delete", "Confirm delete", async () => {
        try {
          await api.deleteStudy(s.id);
          setChildren(msg, notice("info", null, `Deleted study ${s.name} and its jobs.`));
          refreshStudies();
          refreshJobs(true);
        } catch (err) {
          setChildren(msg, errorBox(err, "Could not delete the study"));
        }
      }));
  }

  function updateStudyRow(s) {
    let r = studyRows.get(s.id);
    if (!r) {
      const cells = { name: h("th", { scope: "row" }), status: h("td"), progress: h("td"), jobs: h("td", { class: "num" }), created: h("td"), actions: h("td") };
      r = { tr: h("tr", { dataset: { id: s.id } }, Object.values(cells)), cells, lastStatus: null };
      studyRows.set(s.id, r);
    }
    const c = r.cells;
    setChildren(c.name, h("a", { href: `#/studies/${s.id}` }, s.name), s.preset ? h("div", { class: "small muted" }, `preset ${s.preset}`) : null);
    setChildren(c.status, badge(s.status));
    setChildren(c.progress, progressBar(s.progress, `Progress of study ${s.name}`, studyBarStatus(s)));
    setChildren(c.jobs, `${s.n_jobs}`, h("div", { class: "small muted" }, Object.entries(s.counts).map(([k, v]) => `${v} ${k}`).join(", ")));
    c.created.textContent = when(s.created_at);
    const key = ACTIVE.has(s.status) ? "active" : "final";
    if (r.lastStatus !== key) {
      r.lastStatus = key;
      setChildren(c.actions, studyActions(s));
    }
    return r;
  }

  let studiesTimer = null;
  async function refreshStudies() {
    clearTimeout(studiesTimer);
    if (ctx.signal.aborted) return;
    let page;
    try {
      page = await api.studies({ limit: PAGE, offset: state.soffset }, { signal: ctx.signal });
    } catch (err) {
      if (ctx.signal.aborted) return;
      setChildren(studiesEmpty, errorBox(err, "Could not load the studies"));
      studiesTimer = setTimeout(refreshStudies, 5000);
      return;
    }
    // study filter options for the jobs tab
    const cur = studySel.value || state.study;
    studySel.replaceChildren(h("option", { value: "" }, "any"), ...page.items.map((s) => h("option", { value: s.id, selected: s.id === cur }, `${s.name} (${s.id.slice(0, 8)})`)));
    if (state.study && !page.items.some((s) => s.id === state.study)) studySel.append(h("option", { value: state.study, selected: true }, state.study));
    const seen = new Set();
    page.items.forEach((s, i) => {
      seen.add(s.id);
      const r = updateStudyRow(s);
      if (studiesBody.children[i] !== r.tr) studiesBody.insertBefore(r.tr, studiesBody.children[i] || null);
    });
    for (const [id, r] of studyRows) {
      if (!seen.has(id)) {
        r.tr.remove();
        studyRows.delete(id);
      }
    }
    studiesTable.hidden = !page.items.length;
    setChildren(studiesEmpty, page.items.length ? null : notice("empty", "No studies yet", h("span", {}, "Create one from ", h("a", { href: "#/studies/new" }, "New study"), ": speeds, conditions, rigid against flexible.")));
    const active = page.items.some((s) => ACTIVE.has(s.status));
    if (!ctx.signal.aborted) studiesTimer = setTimeout(refreshStudies, document.hidden ? 10000 : active ? 1500 : 6000);
  }

  const t = tabs([{ id: "jobs", label: "Jobs" }, { id: "studies", label: "Studies" }], (id, panel) => {
    if (id === "jobs") {
      panel.append(
        h("div", { class: "filters", role: "search", "aria-label": "Filter jobs" },
          h("label", { for: "filter-status" }, "Status", statusSel),
          h("label", { for: "filter-study" }, "Study", studySel),
          h("label", { for: "filter-text" }, "Name contains", textIn),
          h("div", { class: "grow" }), compareBtn),
        jobsEmpty, jobsTable, noMatch,
        h("div", { class: "pager" }, jobsInfo, prev, next));
    } else panel.append(studiesBox);
  }, { label: "Jobs or studies", initial: state.tab });
  t.onSelect = (id) => {
    state.tab = id;
    sync();
  };
  main.append(t.el);
  jobsBody.append(h("tr", {}, h("td", { colspan: "9" }, loading("Loading jobs…"))));
  refreshJobs(true);
  refreshStudies();
  const onVis = () => { if (!document.hidden) { refreshJobs(); refreshStudies(); } };
  document.addEventListener("visibilitychange", onVis);
  return () => {
    clearTimeout(jobsTimer);
    clearTimeout(studiesTimer);
    jobsCtrl?.abort();
    document.removeEventListener("visibilitychange", onVis);
  };
}
