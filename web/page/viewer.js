// The page of glview's browser build: loads the module, makes a Viewer on the canvas with the
// query string's options and draws; keys go to the viewer by the window's names. What it did
// is on window.glview (for tests): { ready, error, info, timings }.
import init, { Viewer } from "./glview_web.js";

// The browser's key names where they differ from the window's (glview --help).
const KEYS = { ArrowLeft: "Left", ArrowRight: "Right", ArrowUp: "Up", ArrowDown: "Down", " ": "Space" };

const query = new URLSearchParams(location.search);
const words = query.get("options") ?? "--size 640x480";
const webgl = query.get("webgl") === "1" ? 1 : 2;
const canvas = document.getElementById("view");
const status = document.getElementById("status");
const state = { ready: false, error: null, info: null, timings: {} };
window.glview = state;

function fail(e) {
  state.error = String(e);
  status.textContent = `error: ${state.error}`;
}

try {
  // performance.now() counts from the navigation's start: these are times since page load.
  const t = state.timings;
  t.module_start_ms = performance.now();
  await init();
  t.wasm_ready_ms = performance.now();
  const viewer = new Viewer(canvas, words, webgl);
  t.scene_uploaded_ms = performance.now();
  t.draw_ms = viewer.draw();
  viewer.finish();
  t.first_frame_ms = performance.now();
  state.viewer = viewer;
  state.info = JSON.parse(viewer.info());
  state.ready = true;
  status.textContent = `${state.info.version}, ${state.info.dialect}: first frame after ` +
    `${t.first_frame_ms.toFixed(0)} ms`;
  canvas.addEventListener("keydown", (e) => {
    const name = KEYS[e.key] ?? e.key;
    try {
      if (viewer.key(name)) {
        viewer.draw();
      }
      e.preventDefault();
    } catch (err) {
      // A key the window does not have: not this page's to handle.
      if (!String(err).startsWith("unknown key")) fail(err);
    }
  });
  canvas.focus();
} catch (e) {
  fail(e);
}
