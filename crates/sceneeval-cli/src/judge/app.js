// The judge page of `sceneeval judge`. Every text from the run and the annotations is
// untrusted: the DOM is built with textContent only, never innerHTML; images are shown from
// blob: URLs fetched with the page's token (sceneevalBlobUrl of /sceneeval-api.js).
"use strict";

// `items`: the list from /api/items; `at`: the item shown; `urls`: blob URLs to revoke when
// the next item is shown; `seq`: the item generation (images of an item left behind are not
// shown).
const state = { data: null, at: 0, urls: [], seq: 0, busy: false };
const MAX_OBJECT_VIEWS = 8;

function $(id) { return document.getElementById(id); }

function el(tag, attrs, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

function setStatus(text, isError) {
  const s = $("status");
  s.textContent = text;
  s.className = isError ? "error" : "";
}

function verdictText(v) {
  if (v === true) return "satisfied";
  if (v === false) return "not satisfied";
  return "can't tell";
}

function showProgress() {
  const d = state.data;
  $("progress").textContent = d.judged + " / " + d.total + " judged";
}

// The first item at or after `from` (wrapping) this annotator has not judged; -1 if none.
function firstUnjudged(from) {
  const items = state.data.items;
  for (let k = 0; k < items.length; k++) {
    const i = (from + k) % items.length;
    if (!("verdict" in items[i])) return i;
  }
  return -1;
}

async function image(img, path, seq) {
  try {
    const url = await sceneevalBlobUrl(path);
    if (seq !== state.seq) { URL.revokeObjectURL(url); return; }
    state.urls.push(url);
    img.src = url;
  } catch (e) {
    if (seq !== state.seq) return;
    img.hidden = true;
    img.after(el("span", { class: "note img-error" }, e.message));
  }
}

function show(k) {
  const d = state.data;
  state.at = k;
  state.seq += 1;
  const seq = state.seq;
  for (const u of state.urls) URL.revokeObjectURL(u);
  state.urls = [];
  const item = d.items[k];
  $("where").textContent = "Spec " + (k + 1) + " of " + d.total + ": " + item.scene + ", " +
    item.metric.toUpperCase() + " spec " + item.index;
  $("description").textContent = d.descriptions[item.scene] ||
    "(no description: give the annotation file the run used with --annotations)";
  $("words").textContent = item.words;
  $("spec").textContent = "as annotated: " + item.spec;
  const rv = $("run-verdict");
  if ("run_verdict" in item) {
    rv.hidden = false;
    rv.textContent = "The run's verdict: " + item.run_verdict;
  } else {
    rv.hidden = true;
    rv.textContent = "";
  }
  $("your-verdict").textContent = "verdict" in item ?
    "Your verdict: " + verdictText(item.verdict) + " (answer again to change it)" : "Not judged yet.";
  const top = $("topview");
  top.removeAttribute("src");
  top.hidden = false;
  for (const old of document.querySelectorAll("#images > .img-error")) old.remove();
  $("topview-note").textContent = item.objects.length ?
    "Outlined: " + item.objects.map((o, n) => (n + 1) + ". " + o).join(", ") :
    "The run matched no object to this spec.";
  image(top, "/api/topview?item=" + k, seq);
  const views = $("views");
  views.replaceChildren();
  for (const object of item.objects.slice(0, MAX_OBJECT_VIEWS)) {
    const fig = el("figure");
    for (const kind of ["front", "size"]) {
      const img = el("img", { alt: kind + " view of " + object, "data-kind": kind });
      fig.append(img);
      image(img, "/api/view?item=" + k + "&object=" + encodeURIComponent(object) + "&kind=" + kind, seq);
    }
    fig.append(el("figcaption", {}, (item.objects.indexOf(object) + 1) + ". " + object));
    views.append(fig);
  }
  if (item.objects.length > MAX_OBJECT_VIEWS) {
    views.append(el("p", { class: "note" }, (item.objects.length - MAX_OBJECT_VIEWS) + " more objects not shown"));
  }
  location.hash = "#/" + k;
}

async function answer(satisfied) {
  if (!state.data || state.busy) return;
  state.busy = true;
  const k = state.at;
  try {
    const p = await sceneevalApi("POST", "/api/verdict", { item: k, satisfied });
    state.data.items[k].verdict = satisfied;
    state.data.judged = p.judged;
    state.data.total = p.total;
    showProgress();
    setStatus("Saved: " + verdictText(satisfied) + ".", false);
    const next = firstUnjudged((k + 1) % state.data.items.length);
    if (next < 0) {
      setStatus("Saved. Every spec is judged: you can close the page (Ctrl-C stops the server).", false);
      show(k);
    } else {
      show(next);
    }
  } catch (e) {
    setStatus(e.message, true);
  } finally {
    state.busy = false;
  }
}

function step(delta) {
  if (!state.data) return;
  const n = state.data.items.length;
  show((state.at + delta + n) % n);
  setStatus("", false);
}

document.addEventListener("keydown", e => {
  if (e.ctrlKey || e.metaKey || e.altKey) return;
  const key = e.key.toLowerCase();
  if (key === "y" || key === "1") { e.preventDefault(); answer(true); }
  else if (key === "n" || key === "2") { e.preventDefault(); answer(false); }
  else if (key === "u" || key === "3") { e.preventDefault(); answer(null); }
  else if (key === "b" || key === "arrowleft") { e.preventDefault(); step(-1); }
  else if (key === "s" || key === "arrowright") { e.preventDefault(); step(1); }
});

$("yes").addEventListener("click", () => answer(true));
$("no").addEventListener("click", () => answer(false));
$("unsure").addEventListener("click", () => answer(null));
$("back").addEventListener("click", () => step(-1));
$("skip").addEventListener("click", () => step(1));

sceneevalApi("GET", "/api/items").then(data => {
  state.data = data;
  $("who").textContent = data.annotator + " on " + data.run + " \u2192 " + data.out;
  showProgress();
  const start = firstUnjudged(0);
  if (start < 0) setStatus("Every spec is judged already; answer again to change a verdict.", false);
  show(start < 0 ? 0 : start);
}).catch(e => setStatus(e.message, true));
