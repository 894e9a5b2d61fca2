#include "app/console_page.h"

#include "export/report.h"

namespace mesocap::app {
namespace {

// Sized to be read across a room on a 1920 x 1080 screen: the last shot 60% of the width, the
// next flash position's words 40 px high.
constexpr const char* kPage = R"PAGE(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>mesocap console: @SESSION@</title>
<style>
* { box-sizing: border-box; }
body { margin: 0; background: #111; color: #eee; font: 20px/1.35 system-ui, sans-serif; }
header { display: flex; gap: 28px; align-items: baseline; padding: 8px 20px; background: #222; }
header h1 { font-size: 26px; margin: 0; }
#state { font-size: 24px; color: #9cf; }
main { display: grid; grid-template-columns: 60vw 1fr; gap: 16px; padding: 12px 20px 130px; }
#last img { width: 100%; max-height: 64vh; object-fit: contain; background: #000; display: block; }
#caption { font-size: 28px; margin-top: 6px; }
.ok { color: #5e5; } .bad { color: #f66; } .unknown { color: #bbb; }
#reasons { margin: 4px 0 0 0; font-size: 24px; color: #f99; }
#warnings { margin: 4px 0 0 0; font-size: 24px; color: #fb6; }
#nextwords { font-size: 40px; line-height: 1.2; margin: 6px 0; color: #fd6; }
#nextbox { display: flex; gap: 16px; align-items: center; }
#arrow { flex: none; }
#percent { font-size: 64px; font-weight: 700; }
#bar { height: 22px; background: #333; border-radius: 11px; overflow: hidden; }
#bar div { height: 100%; width: 0; background: #3c6; transition: width .4s; }
#plot { width: 100%; max-height: 29vh; object-fit: contain; background: #fff; margin-top: 8px; }
#boards { font-size: 15px; color: #ccc; }
#buttons { display: flex; flex-wrap: wrap; gap: 10px; margin: 12px 0; }
button { font-size: 24px; padding: 10px 18px; border-radius: 8px; border: 0; background: #357; color: #fff; cursor: pointer; }
button#finish { background: #363; } button#undo { background: #733; }
#error { color: #f66; font-size: 20px; min-height: 1em; }
#process pre { max-height: 20vh; overflow: auto; background: #000; font-size: 15px; padding: 6px; white-space: pre-wrap; }
#report a { font-size: 36px; color: #6cf; display: block; margin: 8px 0; }
#notes { font-size: 18px; color: #fc9; }
footer { position: fixed; bottom: 0; left: 0; right: 0; height: 120px; display: flex; gap: 8px; overflow-x: auto; padding: 8px 20px; background: #1a1a1a; }
footer figure { margin: 0; text-align: center; font-size: 15px; flex: none; }
footer img { height: 90px; display: block; border: 3px solid #444; }
footer figure.usable img { border-color: #3c6; } footer figure.unusable img { border-color: #e44; }
footer figure.rejected { opacity: .35; }
</style></head>
<body data-errors="0" data-version="0" data-shots="0">
<header><h1>mesocap console</h1><span>@SESSION@</span><span id="state">connecting</span></header>
<main>
  <section id="last">
    <img id="lastimg" alt="the last shot">
    <div id="caption">No shot yet.</div>
    <ul id="reasons"></ul>
    <ul id="warnings"></ul>
  </section>
  <aside>
    <div id="nextbox">
      <svg id="arrow" width="220" height="220" viewBox="-110 -110 220 220" aria-label="where to hold the flash next">
        <circle r="100" fill="#222" stroke="#777" stroke-width="3"/>
        <circle r="66" fill="none" stroke="#444"/><circle r="33" fill="none" stroke="#444"/>
        <line id="arrowline" x1="0" y1="0" x2="0" y2="0" stroke="#fd6" stroke-width="12" marker-end="url(#head)"/>
        <defs><marker id="head" markerWidth="4" markerHeight="4" refX="2" refY="2" orient="auto">
          <path d="M0,0 L4,2 L0,4 z" fill="#fd6"/></marker></defs>
      </svg>
      <div><div>Next flash position</div><div id="nextwords">Take the first shots all around the target.</div></div>
    </div>
    <div><span id="percent">0%</span> <span id="covtext">of the reachable light directions covered</span></div>
    <div id="bar"><div></div></div>
    <div id="boards"></div>
    <img id="plot" alt="per board: the light directions measured, still needed and out of reach" hidden>
    <div id="report"></div>
    <div id="process" hidden><div id="processtitle">mesocap process</div><pre id="lines"></pre></div>
    <div id="buttons">
      <button id="shot">Take a shot</button><button id="calib">Calibration shot</button>
      <button id="undo">Undo last shot</button><button id="finish">Finish</button>
    </div>
    <div id="error"></div>
    <ul id="notes"></ul>
  </aside>
</main>
<footer id="shots"></footer>
<script>
"use strict";
const $ = (id) => document.getElementById(id);
let errors = 0;
const countError = () => { errors++; document.body.dataset.errors = String(errors); };
window.addEventListener("error", countError);
window.addEventListener("unhandledrejection", countError);
const consoleError = console.error.bind(console);
console.error = (...args) => { countError(); consoleError(...args); };

let state = null, fetching = false, again = false, plotsShown = 0;
async function refresh() {
  if (fetching) { again = true; return; }
  fetching = true;
  let fresh = null;
  try {
    const response = await fetch("/api/state", { cache: "no-store" });
    if (response.ok) fresh = await response.json();
  } catch (e) { $("state").textContent = "connection lost: retrying"; }
  fetching = false;
  if (fresh) { state = fresh; render(); }  // outside the try: a rendering error counts as one
  if (again) { again = false; refresh(); }
}
function text(node, value) { if (node.textContent !== value) node.textContent = value; }
function list(node, items) {
  node.replaceChildren(...items.map((t) => { const li = document.createElement("li"); li.textContent = t; return li; }));
}
function verdict(shot) {
  if (shot.rejected) return ["undone", "unknown"];
  if (shot.kind === "calib") return ["checkerboard shot", "unknown"];
  if (shot.usable === true) return ["usable", "ok"];
  if (shot.usable === false) return ["not usable", "bad"];
  return shot.analysed ? ["usability known once the rig is located", "unknown"] : ["reading the shot", "unknown"];
}
function renderLast(shots) {
  const live = shots.filter((s) => !s.rejected);
  const last = live.length ? live[live.length - 1] : null;
  if (!last) { text($("caption"), "No shot yet."); list($("reasons"), []); list($("warnings"), []); return; }
  if (last.image && $("lastimg").getAttribute("src") !== last.image) { $("lastimg").src = last.image; $("lastimg").dataset.file = last.file; }
  const [words, cls] = verdict(last);
  const flash = last.flash ? "flash " + last.flash.words : "flash position unknown";
  $("caption").className = cls;
  text($("caption"), last.file + ": " + (last.kind === "calib" ? "" : flash + " · ") + words);
  list($("reasons"), last.why_not || []);
  list($("warnings"), last.warnings || []);
}
function renderNext(next) {
  const line = $("arrowline");
  if (!next.length) { line.setAttribute("x2", 0); line.setAttribute("y2", 0); return; }
  const s = next[0], r = 95 * (90 - s.elevation_deg) / 90, a = s.azimuth_deg * Math.PI / 180;
  line.setAttribute("x2", (r * Math.cos(a)).toFixed(1));
  line.setAttribute("y2", (-r * Math.sin(a)).toFixed(1));
  text($("nextwords"), s.words + " (+" + s.targets_gained + " directions)");
}
function renderCoverage(c) {
  if (!c) return;
  text($("percent"), Math.floor(c.percent) + "%");
  text($("covtext"), "of the reachable light directions covered (" + c.covered + " of " + c.reachable + ")");
  $("bar").firstElementChild.style.width = Math.min(100, c.percent) + "%";
  text($("boards"), c.boards.map((b) => "board " + b.board + ": " + b.covered + "/" + b.reachable + " (" + b.lights + " lights)").join(" · "));
  if ($("plot").getAttribute("src") !== c.plot) { $("plot").src = c.plot; $("plot").hidden = false; ++plotsShown; }
}
function renderShots(shots) {
  const footer = $("shots");
  if (footer.dataset.key === JSON.stringify(shots.map((s) => [s.file, s.thumbnail, s.usable, s.rejected]))) return;
  footer.dataset.key = JSON.stringify(shots.map((s) => [s.file, s.thumbnail, s.usable, s.rejected]));
  footer.replaceChildren(...shots.slice().reverse().map((s) => {
    const f = document.createElement("figure"), img = document.createElement("img"), cap = document.createElement("figcaption");
    if (s.thumbnail) img.src = s.thumbnail;
    img.alt = s.file; img.loading = "lazy";
    cap.textContent = (s.kind === "calib" ? "c" : "#") + s.index;
    f.className = s.rejected ? "rejected" : s.usable === true ? "usable" : s.usable === false ? "unusable" : "";
    f.title = s.file + (s.why_not && s.why_not.length ? ": " + s.why_not.join("; ") : "");
    f.append(img, cap);
    return f;
  }));
}
function renderProcess(p) {
  if (p.state === "idle" && !p.report) return;
  if (p.state !== "idle") {  // finishing: the process's lines and the report take the buttons' place
    $("process").hidden = false;
    $("buttons").hidden = true;
    $("plot").style.maxHeight = "18vh";
    text($("processtitle"), "mesocap process: " + p.state);
  }
  text($("lines"), p.lines.join("\n"));
  $("lines").scrollTop = $("lines").scrollHeight;
  if (p.report && !$("reportlink")) {
    const a = document.createElement("a");
    a.id = "reportlink"; a.href = p.report; a.target = "_blank"; a.textContent = "Open the report and the viewer";
    $("report").replaceChildren(a);
  } else if (p.state === "failed") {
    text($("report"), "process failed (exit " + p.exit_code + "): see the lines above");
  }
}
function render() {
  const c = state.capture;
  text($("state"), state.mode === "review" ? "review" : c.state === "error" ? "camera stopped: " + c.error :
       state.process.state === "running" ? "processing" : state.process.state !== "idle" ? "finished" : c.state + (c.kind === "calib" ? " (checkerboard)" : ""));
  renderLast(state.shots);
  renderNext(state.next);
  renderCoverage(state.coverage);
  renderShots(state.shots);
  list($("notes"), state.notes);
  renderProcess(state.process);
  const capturing = state.mode === "capture" && state.process.state === "idle" && c.state !== "error";
  for (const id of ["shot", "calib", "undo", "finish"]) $(id).disabled = !capturing;
  document.body.dataset.shots = String(state.shots.length);
  document.body.dataset.version = String(state.version);
}
async function post(path) {
  text($("error"), "");
  try {
    const response = await fetch(path, { method: "POST" });
    if (!response.ok) text($("error"), (await response.json()).error || response.statusText);
  } catch (e) { text($("error"), "the console does not answer"); }
}
$("shot").onclick = () => post("/api/shot");
$("calib").onclick = () => post("/api/calibration-shot");
$("undo").onclick = () => post("/api/undo");
$("finish").onclick = () => post("/api/finish");
// When each shot arrived (its event) and when the page showed it: the operator's record.
const arrived = {}, shown = {};
$("lastimg").addEventListener("load", () => {
  const file = $("lastimg").dataset.file;
  if (arrived[file] !== undefined && shown[file] === undefined) shown[file] = (performance.now() - arrived[file]) / 1000;
});
// #still (a screenshot): the state as it is, without the event stream that would keep loading.
if (location.hash !== "#still") {
  const events = new EventSource("/api/events");
  events.onopen = refresh;
  events.onmessage = (message) => {
    const event = JSON.parse(message.data);
    if (event.type === "shot") arrived[event.file] = performance.now();
    refresh();
  };
}
refresh();

// #operator=N (tests and the demo's recording): the page presses its own buttons as an operator
// following it would: calibration shots while the guidance needs them, N flash shots each once
// the last is read, one undo, then finish; its record goes to <body data-operator>.
const sleep = (ms) => new Promise((done) => setTimeout(done, ms));
async function until(test, seconds) {
  for (const end = performance.now() + 1000 * seconds; performance.now() < end; await sleep(50))
    if (state && test(state)) return true;
  throw new Error("the operator waited " + seconds + " s in vain");
}
const count = (s, kind, read) => s.shots.filter((x) => x.kind === kind && (!read || x.analysed)).length;
async function operate(shots, calibration) {
  await until(() => true, 10);
  for (let i = count(state, "calib", false); i < calibration; i++) {
    $("calib").click();
    await until((s) => count(s, "calib", true) === i + 1, 30);
  }
  const percents = [], suggestions = new Set();
  for (let i = count(state, "shot", false); i < shots; i++) {
    $("shot").click();
    await until((s) => count(s, "shot", true) === i + 1 && shown[s.shots[s.shots.length - 1].file] !== undefined, 30);
    if (state.coverage) percents.push(state.coverage.percent);
    if (state.next.length) suggestions.add(state.next[0].words);
  }
  $("undo").click();
  await until((s) => s.shots[s.shots.length - 1].rejected, 30);
  $("finish").click();
  await until((s) => s.process.state === "done" || s.process.state === "failed", 600);
  await sleep(200);
  const link = $("reportlink");
  const report = link ? await fetch(link.href) : null;
  document.body.dataset.operator = JSON.stringify({
    shots: count(state, "shot", false), shown_s: Object.values(shown), percents: percents,
    suggestions: suggestions.size, plots: plotsShown, undone: state.shots.filter((x) => x.rejected).map((x) => x.file),
    process: state.process.state, report: link ? link.getAttribute("href") : null, report_status: report ? report.status : 0,
  });
}
const plan = new URLSearchParams(location.hash.slice(1));
if (plan.has("operator"))
  operate(Number(plan.get("operator")), Number(plan.get("calibration") || 0))
    .catch((e) => { document.body.dataset.operator = JSON.stringify({ error: String(e) }); });
</script>
</body></html>
)PAGE";

}  // namespace

std::string ConsolePage(const std::string& session_name) {
  const std::string escaped = HtmlEscape(session_name);
  std::string page = kPage;
  for (size_t at = page.find("@SESSION@"); at != std::string::npos; at = page.find("@SESSION@", at + escaped.size()))
    page.replace(at, 9, escaped);
  return page;
}

}  // namespace mesocap::app
