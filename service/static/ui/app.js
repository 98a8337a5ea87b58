// The workbench: choose a process, fill its form (or its example), run it as a job, follow
// its progress, cancel it, and see the result: the 3-D view, the quality figures and the
// downloads. Deep links: /ui?process=registration.icp opens a process, /ui?job=ID a job.

import * as api from "./api.js";
import { ProcessForm } from "./form.js";
import { Viewer } from "./viewer.js";

const $ = (sel) => document.querySelector(sel);
const TERMINAL = new Set(["successful", "failed", "dismissed"]);

const state = {
  processes: [],          // summaries from GET /processes
  descriptions: new Map(),
  openapi: null,          // the OpenAPI document, read once for the examples
  catalogExamples: null,
  samples: null,          // the sample data sets (/ui/samples.json), read once
  sampleData: new Map(),  // sample id -> its data file, read when first chosen
  process: null,          // the chosen description
  form: null,
  job: null,              // statusInfo of the job followed
  sent: new Map(),        // job id -> the inputs this page sent (for overlays)
  results: null,
};

const viewer = new Viewer($("#view"));
window.workbench = { state, viewer, ready: null };

// ---------------------------------------------------------------- processes and the form
function familyOf(id) { return id.split(".")[0]; }

function renderProcessList() {
  const q = $("#search").value.trim().toLowerCase();
  const fam = $("#family").value;
  const select = $("#process");
  const current = select.value;
  select.replaceChildren();
  const groups = new Map();
  for (const p of state.processes) {
    if (fam && familyOf(p.id) !== fam) continue;
    const hay = [p.id, p.title, ...(p.keywords || [])].join(" ").toLowerCase();
    if (q && !q.split(/\s+/).every((w) => hay.includes(w))) continue;
    const f = familyOf(p.id);
    if (!groups.has(f)) groups.set(f, document.createElement("optgroup"));
    groups.get(f).label = f;
    const o = document.createElement("option");
    o.value = p.id;
    o.textContent = `${p.id.split(".")[1]} — ${p.title}`;
    o.title = p.title;
    groups.get(f).append(o);
  }
  for (const g of groups.values()) select.append(g);
  if ([...select.options].some((o) => o.value === current)) select.value = current;
}

async function description(id) {
  if (!state.descriptions.has(id)) {
    state.descriptions.set(id, await api.getJSON(`/processes/${encodeURIComponent(id)}`));
  }
  return state.descriptions.get(id);
}

async function chooseProcess(id) {
  const d = await description(id);
  state.process = d;
  $("#process").value = id;
  const info = $("#process-info");
  info.replaceChildren();
  const title = document.createElement("strong");
  title.textContent = d.title;
  const text = document.createElement("div");
  text.textContent = d.description;
  const link = document.createElement("a");
  link.href = `/processes/${encodeURIComponent(id)}`;
  link.textContent = "Full description";
  info.append(title, text);
  if (d.reference) {
    const ref = document.createElement("div");
    ref.className = "ref";
    ref.textContent = `Reference: ${d.reference}`;
    info.append(ref);
  }
  info.append(link);
  state.form = new ProcessForm($("#fields"), d);
  await renderSamples(d);
  const ex = await example(id);
  $("#example").disabled = !ex;
  $("#example").title = ex ? "Fill the form with the process's example" : "This process has no example";
  const url = new URL(location.href);
  url.searchParams.set("process", id);
  url.searchParams.delete("job");
  history.replaceState(null, "", url);
}

/**
 * The example inputs of a process: from the OpenAPI document's execute operation of that
 * process (its request body's examples or example), else from the catalog's examples.
 */
async function example(id) {
  if (state.openapi === null) {
    try { state.openapi = await api.getJSON("/openapi.json"); } catch { state.openapi = {}; }
  }
  const op = state.openapi.paths?.[`/processes/${id}/execution`]?.post;
  const content = op?.requestBody?.content?.["application/json"];
  let body = null;
  if (content?.examples && Object.keys(content.examples).length) {
    const first = Object.values(content.examples)[0];
    body = first?.value ?? null;
  } else if (content?.example) {
    body = content.example;
  }
  if (body) return body.inputs ?? body;
  if (state.catalogExamples === null) {
    try { state.catalogExamples = await api.getJSON("/ui/examples.json"); } catch { state.catalogExamples = {}; }
  }
  const ex = state.catalogExamples[id];
  return ex && Object.keys(ex).length ? ex : null;
}

// ---------------------------------------------------------------- sample data
/** The sample data sets offered for a process (samples.json names the processes each suits). */
async function samplesFor(d) {
  if (state.samples === null) {
    try { state.samples = (await api.getJSON("/ui/samples.json")).samples || []; } catch { state.samples = []; }
  }
  return state.samples.filter((s) => s.processes.includes(d.id) && s.fills.some((n) => n in (d.inputs || {})));
}

async function renderSamples(d) {
  const select = $("#sample");
  select.replaceChildren(new Option("Sample data…", ""));
  $("#sample-info").hidden = true;
  const offered = await samplesFor(d);
  for (const s of offered) select.append(new Option(s.title, s.id));
  select.hidden = offered.length === 0;
  select.value = "";
}

/** Fills the form with a sample: its members named like the process's inputs, the other
 * inputs back to their defaults; says where the data come from and under what licence. */
async function fillSample(sampleId) {
  const s = (state.samples || []).find((x) => x.id === sampleId);
  if (!s || !state.process) return;
  showProblem(null);
  let data = state.sampleData.get(s.id);
  if (!data) {
    try { data = await api.getJSON(s.file); } catch (e) { showProblem(e); return; }
    state.sampleData.set(s.id, data);
  }
  const inputs = {};
  for (const name of s.fills) if (name in (state.process.inputs || {}) && name in data) inputs[name] = data[name];
  state.form.fill(inputs);
  const info = $("#sample-info");
  info.textContent = `${data.title}. ${data.description} Source: ${data.source}. Licence: ${data.licence}.`;
  info.hidden = false;
}

// ---------------------------------------------------------------- jobs
function showProblem(err) {
  const box = $("#problem");
  if (!err) { box.hidden = true; box.textContent = ""; return; }
  const p = err.problem || {};
  const lines = [p.title ? `${p.title}: ${p.detail ?? ""}` : err.message];
  for (const e of p.errors || []) lines.push(`• ${e.input}: ${e.message}`);
  box.textContent = lines.join("\n");
  box.hidden = false;
}

function showStatus(info) {
  state.job = info;
  const line = $("#job-line");
  line.dataset.status = info.status;
  line.dataset.job = info.jobID;
  line.replaceChildren();
  const s = document.createElement("span");
  s.className = `status-${info.status}`;
  s.textContent = info.status;
  line.append(`${info.processID} · job ${info.jobID.slice(0, 8)} · `, s);
  $("#progress").value = info.progress ?? 0;
  $("#job-message").textContent = info.message || "";
  $("#cancel").disabled = TERMINAL.has(info.status);
  $("#run").disabled = !TERMINAL.has(info.status);
}

let pollTimer = null;

async function follow(jobId) {
  clearTimeout(pollTimer);
  let info;
  try {
    info = await api.getJSON(`/jobs/${encodeURIComponent(jobId)}`);
  } catch (e) {
    showProblem(e);
    $("#run").disabled = false;
    $("#cancel").disabled = true;
    return;
  }
  if (state.job && state.job.jobID !== jobId) return;  // another job was chosen meanwhile
  showStatus(info);
  if (!TERMINAL.has(info.status)) {
    pollTimer = setTimeout(() => follow(jobId), 250);
    return;
  }
  if (info.status === "successful") await showResults(info);
  else await showFailure(info);
  refreshJobs();
}

async function showFailure(info) {
  if (info.status === "failed") {
    try { await api.getJSON(`/jobs/${encodeURIComponent(info.jobID)}/results`); } catch (e) { showProblem(e); }
  }
}

async function run(event) {
  event.preventDefault();
  showProblem(null);
  if (!state.process) return;
  let read;
  try { read = state.form.read(); } catch (e) { showProblem(e); return; }
  $("#run").disabled = true;
  try {
    const info = await api.execute(state.process.id, read.inputs, read.files);
    state.sent.set(info.jobID, read.inputs);
    state.job = info;
    clearResults();
    showStatus(info);
    follow(info.jobID);
  } catch (e) {
    showProblem(e);
    state.form.showErrors(e.problem);
    $("#run").disabled = false;
  }
}

async function cancel() {
  if (!state.job) return;
  $("#cancel").disabled = true;
  try {
    const info = await api.dismiss(state.job.jobID);
    clearTimeout(pollTimer);
    showStatus(info);
    refreshJobs();
  } catch (e) { showProblem(e); }
}

// ---------------------------------------------------------------- results
function clearResults() {
  $("#results-box").hidden = true;
  $("#quality tbody").replaceChildren();
  $("#downloads").replaceChildren();
  $("#layers").replaceChildren();
  $("#timeline").hidden = true;
  $("#legend").hidden = true;
  $("#empty").hidden = false;
  viewer.clear();
}

/** The scalar figures of a results document: name -> number, boolean, string or null. */
export function scalars(doc, prefix = "", out = []) {
  for (const [k, v] of Object.entries(doc || {})) {
    const name = prefix ? `${prefix}.${k}` : k;
    if (v === null || ["number", "boolean", "string"].includes(typeof v)) out.push([name, v]);
    else if (v && typeof v === "object" && !Array.isArray(v) && !api.isArrayValue(v)) scalars(v, name, out);
  }
  return out;
}

function format(v) {
  if (typeof v === "number") {
    if (Number.isInteger(v)) return String(v);
    const a = Math.abs(v);
    return a !== 0 && (a < 1e-3 || a >= 1e6) ? v.toExponential(5) : String(Number(v.toPrecision(6)));
  }
  if (v === null) return "—";
  return String(v);
}

function download(href, text) {
  const li = document.createElement("li");
  const a = document.createElement("a");
  a.href = href;
  a.textContent = text;
  a.setAttribute("download", "");
  li.append(a);
  $("#downloads").append(li);
}

async function showResults(info) {
  const id = info.jobID;
  const base = `/jobs/${encodeURIComponent(id)}/results`;
  let doc;
  try {
    doc = await api.getJSON(base, { Prefer: "arrays=binary" });
  } catch (e) { showProblem(e); return; }
  state.results = doc;
  const body = $("#quality tbody");
  body.replaceChildren();
  for (const [name, v] of scalars(doc)) {
    const tr = document.createElement("tr");
    tr.dataset.name = name;
    const th = document.createElement("th");
    th.scope = "row";
    th.textContent = name;
    const td = document.createElement("td");
    td.dataset.value = JSON.stringify(v);
    td.textContent = format(v);
    td.title = String(v);
    tr.append(th, td);
    body.append(tr);
  }
  if (!body.children.length) {
    const tr = document.createElement("tr");
    tr.innerHTML = '<td colspan="2">No scalar figures in these results.</td>';
    body.append(tr);
  }
  $("#downloads").replaceChildren();
  download(base, "Results (JSON)");
  const family = familyOf(info.processID);
  const sent = state.sent.get(id) || null;
  const decoded = (v) => (v ? api.decodeArray(v) : null);
  const labelsOf = () => {
    const l = doc.labels ?? doc.predictions ?? sent?.labels;
    if (Array.isArray(l)) return l;
    const d = decoded(l);
    return d ? Array.from(d.data) : null;
  };
  let shown = false;
  try {
    const glb = await api.getBinary(`${base}?f=glb`, "model/gltf-binary");
    download(`${base}?f=glb`, "Geometry (GLB)");
    const r = await viewer.showGLB(glb, { family, inputs: sent, labels: labelsOf() });
    $("#timeline").hidden = !r.animated;
    $("#point-size").value = String(r.pointSize);
    shown = true;
  } catch (e) {
    if (!(e instanceof api.ProblemError && e.status === 406)) { showProblem(e); }
  }
  if (!shown) shown = viewer.showSets({ inputs: sent, pairs: decoded(doc.pairs) });
  for (const [name, v] of Object.entries(doc)) {
    // numeric arrays come as typed binary arrays (strings and booleans stay lists): .npy
    if (v && typeof v === "object" && typeof v.dtype === "string" && typeof v.data === "string") download(`${base}/${encodeURIComponent(name)}?f=npy`, `${name} (NPY)`);
  }
  $("#empty").hidden = shown;
  $("#empty").textContent = shown ? "" : "These results hold no geometry to show.";
  renderLayers();
  renderLegend();
  $("#results-box").hidden = false;
  document.body.dataset.shown = id;
}

function renderLegend() {
  const box = $("#legend");
  const legend = viewer.legend();
  box.replaceChildren();
  box.hidden = (!legend || legend.size < 2) && viewer.colorBy !== "index";
  if (box.hidden) return;
  if (!legend || legend.size < 2) {
    box.textContent = "Coloured by point index (first → last)";
    return;
  }
  const title = document.createElement("div");
  title.textContent = "Colour by label";
  box.append(title);
  for (const [label, color] of legend) {
    const row = document.createElement("div");
    const sw = document.createElement("span");
    sw.className = "swatch";
    sw.style.background = color;
    row.append(sw, ` ${label}`);
    box.append(row);
  }
}

function renderLayers() {
  const box = $("#layers");
  box.replaceChildren();
  for (const l of viewer.layers) {
    const label = document.createElement("label");
    const cb = document.createElement("input");
    cb.type = "checkbox";
    cb.checked = l.object.visible;
    cb.dataset.layer = l.name;
    cb.addEventListener("change", () => viewer.setVisible(l.name, cb.checked));
    label.append(cb);
    if (l.color) {
      const sw = document.createElement("span");
      sw.className = "swatch";
      sw.style.background = l.color;
      label.append(sw);
    }
    label.append(l.name);
    box.append(label);
  }
}

// ---------------------------------------------------------------- the jobs list
async function refreshJobs() {
  if ($("#pane-jobs").hidden) return;
  let list;
  try { list = await api.getJSON("/jobs?limit=30"); } catch (e) { return; }
  const body = $("#jobs tbody");
  body.replaceChildren();
  for (const j of list.jobs) {
    const tr = document.createElement("tr");
    tr.dataset.job = j.jobID;
    const cells = [j.processID, `${j.status}${TERMINAL.has(j.status) ? "" : ` ${j.progress ?? 0}%`}`,
      (j.created || "").replace("T", " ").slice(0, 19)];
    cells.forEach((c, i) => {
      const td = document.createElement("td");
      td.textContent = c;
      if (i === 1) td.className = `status-${j.status}`;
      tr.append(td);
    });
    const td = document.createElement("td");
    const b = document.createElement("button");
    b.type = "button";
    b.className = "secondary";
    b.textContent = "Open";
    b.setAttribute("aria-label", `Open job ${j.jobID}`);
    b.addEventListener("click", () => openJob(j.jobID));
    td.append(b);
    tr.append(td);
    body.append(tr);
  }
}

async function openJob(jobId) {
  selectTab("run");
  showProblem(null);
  clearResults();
  state.job = { jobID: jobId };
  try {
    const info = await api.getJSON(`/jobs/${encodeURIComponent(jobId)}`);
    await chooseProcess(info.processID).catch(() => {});
    state.job = info;
    const url = new URL(location.href);
    url.searchParams.set("job", jobId);
    history.replaceState(null, "", url);
    follow(jobId);
  } catch (e) { showProblem(e); }
}

function selectTab(which) {
  for (const t of ["run", "jobs"]) {
    $(`#tab-${t}`).setAttribute("aria-selected", String(t === which));
    $(`#pane-${t}`).hidden = t !== which;
  }
  if (which === "jobs") refreshJobs();
}

// ---------------------------------------------------------------- start
function wire() {
  $("#api-key").value = api.apiKey();
  $("#api-key").addEventListener("change", (e) => api.setApiKey(e.target.value.trim()));
  $("#search").addEventListener("input", renderProcessList);
  $("#family").addEventListener("change", renderProcessList);
  $("#process").addEventListener("change", (e) => { if (e.target.value) chooseProcess(e.target.value); });
  $("#example").addEventListener("click", async () => {
    if (!state.process) return;
    state.form.fill(await example(state.process.id));
    $("#sample").value = "";
    $("#sample-info").hidden = true;
  });
  $("#sample").addEventListener("change", (e) => { if (e.target.value) fillSample(e.target.value); });
  $("#form").addEventListener("submit", run);
  $("#cancel").addEventListener("click", cancel);
  $("#tab-run").addEventListener("click", () => selectTab("run"));
  $("#tab-jobs").addEventListener("click", () => selectTab("jobs"));
  $("#jobs-refresh").addEventListener("click", refreshJobs);
  $("#up-axis").addEventListener("change", (e) => viewer.setUp(e.target.value));
  $("#point-size").addEventListener("input", (e) => viewer.setPointSize(Number(e.target.value)));
  $("#fit").addEventListener("click", () => viewer.fit());
  const slider = $("#time");
  viewer.onTime = (t, d) => { slider.value = String(Math.round((t / d) * 1000)); $("#time-label").value = (t / d).toFixed(2); };
  slider.addEventListener("input", () => {
    const d = viewer.duration || 1;
    viewer.setTime((Number(slider.value) / 1000) * d);
    $("#time-label").value = (Number(slider.value) / 1000).toFixed(2);
  });
  $("#play").addEventListener("click", () => {
    viewer.playing = !viewer.playing;
    $("#play").textContent = viewer.playing ? "Pause" : "Play";
    $("#play").setAttribute("aria-label", viewer.playing ? "Pause" : "Play");
  });
  const hover = $("#hover");
  viewer.onHover = (h) => {
    if (!h) { hover.hidden = true; return; }
    hover.hidden = false;
    hover.style.left = `${h.x}px`;
    hover.style.top = `${h.y}px`;
    hover.textContent = `${h.layer ? `${h.layer} ` : ""}#${h.index}${h.label !== undefined ? ` · label ${h.label}` : ""}`;
  };
  setInterval(() => { if (!$("#pane-jobs").hidden) refreshJobs(); }, 3000);
}

async function start() {
  wire();
  const list = await api.getJSON("/processes");
  state.processes = list.processes;
  const fams = [...new Set(state.processes.map((p) => familyOf(p.id)))];
  for (const f of fams) {
    const o = document.createElement("option");
    o.value = f;
    o.textContent = f;
    $("#family").append(o);
  }
  renderProcessList();
  const params = new URLSearchParams(location.search);
  const job = params.get("job");
  const wanted = params.get("process");
  if (job) await openJob(job);
  else await chooseProcess(wanted && state.processes.some((p) => p.id === wanted) ? wanted : state.processes[0].id);
  document.body.dataset.ready = "true";
}

window.workbench.ready = start().catch((e) => { showProblem(e); document.body.dataset.ready = "error"; });
