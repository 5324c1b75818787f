// The review page of `sceneeval annotations review`. Every text from the files is untrusted:
// the DOM is built with textContent and form values only, never innerHTML. Validation is the
// server's (the project's validator); this script only shows its findings.
"use strict";

// Requests go through `sceneevalApi` (/sceneeval-api.js, the page server's client), which
// carries the page's token.

// The four annotation kinds: the row field, the column name, the columns of an entry. The
// last column takes the rest of the entry (several objects or architecture elements).
const KINDS = [
  { field: "obj_count", name: "ObjCount", columns: ["quantifier", "count", "category"] },
  { field: "obj_attr", name: "ObjAttr", columns: ["quantifier", "count", "category", "attribute"] },
  { field: "oo_rel", name: "OORel", columns: ["quantifier", "count", "relationship", "anchor index", "objects (a,b,...)"] },
  { field: "oa_rel", name: "OARel", columns: ["quantifier", "count", "relationship", "object", "architecture (a,b,...)"] },
];

// `dirty`: the open candidate has edits not saved yet (saved when another candidate opens or
// the page is hidden or closed, so that a closed tab loses nothing).
const state = { list: [], current: null, candidate: null, validateTimer: null, validateSeq: 0, dirty: false };

function el(tag, attrs, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

function $(id) { return document.getElementById(id); }

function api(method, path, body) {
  return sceneevalApi(method, path, body);
}

function setStatus(text, isError) {
  const s = $("status");
  s.textContent = text;
  s.className = isError ? "error" : "";
}

// ---------------------------------------------------------------- the list

async function loadList() {
  const data = await api("GET", "/api/candidates");
  state.list = data.candidates;
  $("files").textContent = data.file + " \u2192 " + data.accepted_file;
  renderList();
}

function visible() {
  const s = $("filter-state").value;
  const words = $("filter-text").value.toLowerCase().split(/\s+/).filter(w => w);
  return state.list.filter(c =>
    (s === "all" || c.state === s) &&
    words.every(w => c.id.toLowerCase() === w || c.description.toLowerCase().includes(w)));
}

function renderList() {
  const ul = $("candidates");
  ul.replaceChildren();
  const shown = visible();
  const n = { pending: 0, accepted: 0, rejected: 0 };
  for (const c of state.list) n[c.state] += 1;
  $("counts").textContent = state.list.length + " candidates: " + n.pending + " pending, " +
    n.accepted + " accepted, " + n.rejected + " rejected; " + shown.length + " shown";
  for (const c of shown) {
    const li = el("li", { "data-id": c.id });
    if (c.id === state.current) li.className = "current";
    li.append(el("span", { class: "id" }, c.id), el("span", { class: "state " + c.state }, c.state));
    if (c.errors) li.append(el("span", { class: "badge errors" }, c.errors + " error(s)"));
    if (c.warnings) li.append(el("span", { class: "badge warnings" }, c.warnings + " warning(s)"));
    if (c.from_rejected) li.append(el("span", { class: "badge" }, "rejected by generate"));
    li.append(el("div", {}, "[" + c.difficulty + "] " + c.description));
    li.addEventListener("click", () => { location.hash = "#/c/" + encodeURIComponent(c.id); });
    ul.append(li);
  }
}

// ---------------------------------------------------------------- one candidate

function splitEntry(text, n) {
  const parts = text.split(",").map(p => p.trim());
  const cells = parts.slice(0, n - 1);
  while (cells.length < n - 1) cells.push("");
  cells.push(parts.slice(n - 1).join(","));
  return cells;
}

function joinEntry(cells) {
  const trimmed = cells.map(c => c.trim());
  if (trimmed.every(c => c === "")) return null;
  while (trimmed.length && trimmed[trimmed.length - 1] === "") trimmed.pop();
  return trimmed.join(",").replace(/[\r\n;]+/g, " ");
}

function entryRow(kind, cells) {
  const tr = el("tr");
  kind.columns.forEach((col, i) => {
    const td = el("td", i < 2 ? { class: "num" } : {});
    const input = el("input", { type: "text", "aria-label": kind.name + " " + col, "data-col": String(i) });
    input.value = cells[i] || "";
    input.addEventListener("input", scheduleValidate);
    td.append(input);
    tr.append(td);
  });
  const td = el("td");
  const del = el("button", { type: "button", class: "delete", title: "delete this entry" }, "\u00d7");
  del.addEventListener("click", () => { tr.remove(); scheduleValidate(); });
  td.append(del);
  tr.append(td);
  return tr;
}

function renderTables(content) {
  const box = $("tables");
  box.replaceChildren();
  for (const kind of KINDS) {
    const div = el("div", { class: "kind", id: "kind-" + kind.field });
    div.append(el("h3", {}, kind.name));
    const table = el("table", { "data-field": kind.field });
    const head = el("tr");
    for (const col of kind.columns) head.append(el("th", {}, col));
    head.append(el("th", {}, ""));
    const thead = el("thead");
    thead.append(head);
    const tbody = el("tbody");
    for (const entry of content[kind.field]) tbody.append(entryRow(kind, splitEntry(entry, kind.columns.length)));
    table.append(thead, tbody);
    const add = el("button", { type: "button", class: "add" }, "Add " + kind.name + " entry");
    add.addEventListener("click", () => {
      const tr = entryRow(kind, []);
      tbody.append(tr);
      tr.querySelector("input").focus();
    });
    div.append(table, add);
    box.append(div);
  }
}

function currentContent() {
  const content = {
    description: $("description").value.trim(),
    difficulty: $("difficulty").value,
  };
  for (const kind of KINDS) {
    const rows = document.querySelectorAll('table[data-field="' + kind.field + '"] tbody tr');
    content[kind.field] = [];
    for (const tr of rows) {
      const entry = joinEntry(Array.from(tr.querySelectorAll("input"), i => i.value));
      if (entry !== null) content[kind.field].push(entry);
    }
  }
  return content;
}

function renderFindings(findings) {
  const ul = $("findings");
  ul.replaceChildren();
  if (!findings.length) {
    ul.append(el("li", { class: "none" }, "no findings"));
    return;
  }
  for (const f of findings) {
    let text = f.severity + " " + f.code + " in " + f.field;
    if (f.entry) text += ' "' + f.entry + '"';
    text += ": " + f.message;
    if (f.suggestion) text += " (suggestion: " + f.suggestion + ")";
    ul.append(el("li", { class: f.severity }, text));
  }
}

function renderCandidate(detail) {
  const c = detail.candidate;
  state.candidate = c;
  state.current = c.id;
  $("cand-title").textContent = "Candidate " + c.id;
  const st = $("cand-state");
  st.textContent = c.state;
  st.className = "state " + c.state;
  let source = c.source.kind === "file" ? "row " + (c.source.row + 1) + " of the file" :
    "line " + (c.source.line + 1) + " of the rejected file";
  if (c.generator_reason) {
    const r = c.generator_reason;
    source += "; rejected by generate: " + r.reason;
    if (r.problems) source += ": " + r.problems;
    if (r.near_description) source += ' (near ' + r.near_id + ': "' + r.near_description + '", ' + r.score + ")";
    if (r.detail) source += ": " + r.detail;
  }
  $("cand-source").textContent = source;
  $("cand-note").textContent = c.reviewer_note ? "Rejected by the reviewer: " + c.reviewer_note : "";
  $("description").value = c.content.description;
  const d = $("difficulty");
  if (!Array.from(d.options).some(o => o.value === c.content.difficulty)) {
    d.append(el("option", { value: c.content.difficulty }, c.content.difficulty));
  }
  d.value = c.content.difficulty;
  $("reject-note").value = c.reviewer_note || "";
  renderTables(c.content);
  renderFindings(detail.findings);
  $("editor").hidden = false;
  $("stats").hidden = true;
  state.dirty = false;
  renderList();
}

// Saves the open candidate's edits, if any, before another view opens.
async function saveIfDirty() {
  if (!state.dirty || !state.candidate) return;
  const id = state.candidate.id;
  try {
    await api("POST", "/api/save", { id, content: currentContent() });
    state.dirty = false;
    await loadList();
    setStatus("Saved the edit of " + id + ".", false);
  } catch (e) {
    setStatus("The edit of " + id + " was not saved: " + e.message, true);
  }
}

// The page is hidden or closed: the edits go out in a request that outlives the page.
function flushOnHide() {
  if (!state.dirty || !state.candidate) return;
  state.dirty = false;
  sceneevalApi("POST", "/api/save", { id: state.candidate.id, content: currentContent() }, { keepalive: true })
    .catch(() => {});
}

async function openCandidate(id) {
  try {
    renderCandidate(await api("GET", "/api/candidate?id=" + encodeURIComponent(id)));
  } catch (e) {
    setStatus(e.message, true);
  }
}

function scheduleValidate() {
  state.dirty = true;
  clearTimeout(state.validateTimer);
  state.validateTimer = setTimeout(validateNow, 200);
}

async function validateNow() {
  if (!state.candidate) return;
  const seq = ++state.validateSeq;
  try {
    const data = await api("POST", "/api/validate", { id: state.candidate.id, content: currentContent() });
    if (seq === state.validateSeq) renderFindings(data.findings);
  } catch (e) {
    setStatus(e.message, true);
  }
}

async function decide(action) {
  if (!state.candidate) return;
  const body = { id: state.candidate.id, content: currentContent() };
  if (action === "reject") {
    body.note = $("reject-note").value;
    if (!body.note.trim()) {
      setStatus("Write the reason for rejecting first.", true);
      $("reject-note").focus();
      return;
    }
  }
  try {
    const detail = await api("POST", "/api/" + action, body);
    await loadList();
    renderCandidate(detail);
    const done = { save: "Saved.", accept: "Accepted.", reject: "Rejected." }[action];
    setStatus(done + " (" + detail.candidate.state + ")", false);
    if (action !== "save") step(1, true);
  } catch (e) {
    setStatus(e.message, true);
  }
}

// Moves in the list; after a decision, to the next candidate still shown, if any.
function step(delta, quiet) {
  const shown = visible();
  if (!shown.length) return;
  let i = shown.findIndex(c => c.id === state.current);
  if (i < 0) {
    i = 0;
  } else {
    i += delta;
    if (i < 0 || i >= shown.length) {
      if (!quiet) setStatus("no " + (delta > 0 ? "next" : "previous") + " candidate in the list", false);
      return;
    }
  }
  location.hash = "#/c/" + encodeURIComponent(shown[i].id);
}

// ---------------------------------------------------------------- statistics

async function showStats() {
  $("editor").hidden = true;
  $("stats").hidden = false;
  try {
    const data = await api("GET", "/api/stats");
    $("stats-rows").textContent = data.rows + " accepted row(s), as sceneeval annotations stats prints them.";
    const table = $("stats-table");
    table.replaceChildren();
    // The Markdown table of `annotations stats`, one cell per `|`-separated part.
    const lines = data.markdown.split("\n").filter(l => l.startsWith("|") && !l.startsWith("|---"));
    lines.forEach((line, i) => {
      const tr = el("tr");
      for (const cell of line.split("|").slice(1, -1)) tr.append(el(i === 0 ? "th" : "td", {}, cell.trim()));
      table.append(tr);
    });
  } catch (e) {
    $("stats-rows").textContent = e.message;
  }
}

// ---------------------------------------------------------------- routing and keys

async function route() {
  await saveIfDirty();
  const hash = location.hash;
  if (hash === "#/stats") {
    showStats();
  } else if (hash.startsWith("#/c/")) {
    openCandidate(decodeURIComponent(hash.slice(4)));
  } else {
    $("stats").hidden = true;
    const first = visible()[0] || state.list[0];
    if (first) location.hash = "#/c/" + encodeURIComponent(first.id);
  }
}

document.addEventListener("keydown", e => {
  if ((e.ctrlKey || e.metaKey) && !e.shiftKey && e.key === "s") { e.preventDefault(); decide("save"); }
  else if ((e.ctrlKey || e.metaKey) && e.key === "Enter") { e.preventDefault(); decide("accept"); }
  else if ((e.ctrlKey || e.metaKey) && e.shiftKey && (e.key === "X" || e.key === "x")) { e.preventDefault(); decide("reject"); }
  else if (e.altKey && e.key === "ArrowDown") { e.preventDefault(); step(1, false); }
  else if (e.altKey && e.key === "ArrowUp") { e.preventDefault(); step(-1, false); }
});

$("save").addEventListener("click", () => decide("save"));
$("accept").addEventListener("click", () => decide("accept"));
$("reject").addEventListener("click", () => decide("reject"));
$("next").addEventListener("click", () => step(1, false));
$("prev").addEventListener("click", () => step(-1, false));
$("description").addEventListener("input", scheduleValidate);
$("difficulty").addEventListener("change", scheduleValidate);
$("filter-state").addEventListener("change", renderList);
$("filter-text").addEventListener("input", renderList);
window.addEventListener("hashchange", route);
window.addEventListener("pagehide", flushOnHide);
document.addEventListener("visibilitychange", () => {
  if (document.visibilityState === "hidden") flushOnHide();
});

loadList().then(route).catch(e => setStatus(e.message, true));
