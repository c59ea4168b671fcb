// The page: input (dropped files or a built-in example), the operation, the viewer and the
// stats. All computing happens in worker.js; this thread only draws, so it never freezes.
//
// Links that run a demo on load: index.html?demo=union runs the built-in union and writes its
// stats as one JSON object into <pre id="stats">; index.html?demo=bad loads a malformed file
// and shows csgkit's message in <div id="error">. Any example name works after demo=.
import { Viewer } from "./viewer.js";
import { EXAMPLES } from "./examples.js";

const $ = (id) => document.getElementById(id);
const viewer = new Viewer($("canvas"));
const worker = new Worker("worker.js", { type: "module" });

/** What the page shows now: the operand names, whether a result exists. */
let operandCount = 0;
let hasResult = false;
/** Set by ?demo=NAME: run the example's operation once its operands are loaded. */
const demo = new URLSearchParams(location.search).get("demo");
let demoPending = Boolean(demo);

for (const [name, { label }] of Object.entries(EXAMPLES)) {
  $("example").append(new Option(label, name));
}

function showError(message) {
  $("error").textContent = message;
  $("error").hidden = !message;
}

function setBusy(busy, text = "") {
  $("busy").hidden = !busy;
  $("stage").textContent = text;
  $("run").disabled = busy || operandCount < 2;
  for (const button of document.querySelectorAll(".save")) button.disabled = busy || !hasResult;
}

function post(message, busyText) {
  showError("");
  setBusy(true, busyText);
  worker.postMessage(message);
}

function run() {
  $("stats").textContent = "";
  $("progress").removeAttribute("value");
  post({ type: "run", op: $("op").value }, "starting");
}

worker.onmessage = ({ data }) => {
  switch (data.type) {
    case "progress": {
      const { stage, done, total } = data;
      $("stage").textContent = `${stage} ${done}/${total}`;
      $("progress").max = Math.max(total, 1);
      $("progress").value = done;
      break;
    }
    case "operands": {
      viewer.clear();
      hasResult = false;
      operandCount = data.operands.length;
      const items = data.operands.map(({ name, faces }) => `${name}: ${faces} faces`);
      if (items.length > 8) items.splice(6, items.length - 7, `… ${items.length - 7} more`);
      $("operands").replaceChildren(...items.map((text) => Object.assign(document.createElement("li"), { textContent: text })));
      data.operands.forEach(({ drawable }, i) => viewer.setLayer(`operand ${i}`, drawable));
      viewer.frame();
      if (data.op) $("op").value = data.op;
      $("stats").textContent = "";
      setBusy(false);
      if (demoPending) {
        demoPending = false;
        run();
      }
      break;
    }
    case "result": {
      hasResult = true;
      $("stats").textContent = JSON.stringify(data.stats);
      viewer.setLayer("result", data.drawable, { visible: $("show-result").checked });
      // The operands stay as translucent ghosts over the result, shown on demand.
      for (let i = 0; i < operandCount; i++) {
        const { drawable } = viewer.layers.get(`operand ${i}`);
        viewer.setLayer(`operand ${i}`, drawable, { ghost: true, visible: $("show-operands").checked });
      }
      setBusy(false);
      document.body.dataset.state = "done";
      break;
    }
    case "saved": {
      const url = URL.createObjectURL(new Blob([data.bytes]));
      Object.assign(document.createElement("a"), { href: url, download: data.name }).click();
      setTimeout(() => URL.revokeObjectURL(url), 1000);
      setBusy(false);
      break;
    }
    case "error": {
      showError(data.message);
      demoPending = false;
      setBusy(false);
      document.body.dataset.state = "error";
      break;
    }
  }
};

worker.onerror = (event) => {
  showError(`the worker stopped: ${event.message}`);
  setBusy(false);
};

function showOperands(show) {
  for (let i = 0; i < operandCount; i++) viewer.setVisible(`operand ${i}`, show || !hasResult);
}

async function loadFiles(fileList) {
  const files = await Promise.all(
    [...fileList].map(async (file) => ({ name: file.name, bytes: new Uint8Array(await file.arrayBuffer()) })),
  );
  $("example").value = "";
  post({ type: "load", files }, "reading files");
}

const drop = $("drop");
drop.addEventListener("dragover", (event) => {
  event.preventDefault();
  drop.classList.add("over");
});
drop.addEventListener("dragleave", () => drop.classList.remove("over"));
drop.addEventListener("drop", (event) => {
  event.preventDefault();
  drop.classList.remove("over");
  loadFiles(event.dataTransfer.files);
});
$("files").addEventListener("change", (event) => loadFiles(event.target.files));
$("example").addEventListener("change", (event) => {
  if (event.target.value) post({ type: "example", name: event.target.value }, "loading example");
});
$("run").addEventListener("click", run);
for (const button of document.querySelectorAll(".save")) {
  button.addEventListener("click", () => post({ type: "save", name: `csgkit-result.${button.dataset.ext}` }, "writing"));
}
$("edges").addEventListener("change", (event) => viewer.setEdges(event.target.checked));
$("show-operands").addEventListener("change", (event) => showOperands(event.target.checked));
$("show-result").addEventListener("change", (event) => viewer.setVisible("result", event.target.checked));

setBusy(false);
if (demo) {
  $("example").value = demo;
  post({ type: "example", name: demo }, "loading example");
}
