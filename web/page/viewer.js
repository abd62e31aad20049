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
        redraw();
      }
      e.preventDefault();
    } catch (err) {
      // A key the window does not have: not this page's to handle.
      if (!String(err).startsWith("unknown key")) fail(err);
    }
  });
  // Drags and wheel notches add up between frames: one draw per animation frame.
  let pending = false;
  const redraw = () => {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      try {
        viewer.draw();
        state.frames = (state.frames ?? 1) + 1;
      } catch (err) {
        fail(err);
      }
    });
  };
  canvas.addEventListener("pointerdown", (e) => {
    if (e.button === 0) canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!canvas.hasPointerCapture(e.pointerId) || (e.movementX === 0 && e.movementY === 0)) return;
    try {
      viewer.drag(e.movementX, e.movementY);
      redraw();
    } catch (err) {
      fail(err);
    }
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    // A notch is ~100 pixels of deltaY (3 lines); scrolling down (deltaY > 0) comes towards
    // the user: zoom out, as the window's wheel.
    const per = e.deltaMode === 1 ? 3 : e.deltaMode === 2 ? 1 : 100;
    try {
      viewer.wheel(-e.deltaY / per);
      redraw();
    } catch (err) {
      fail(err);
    }
  }, { passive: false });
  canvas.focus();
} catch (e) {
  fail(e);
}
