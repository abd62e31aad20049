// glview's renderer started on a canvas: what the live lesson page (glview export --live) and
// glview serve's local mode share. It checks the browser, opens a Viewer on the files given,
// draws the first frames and applies the speed rule. Classic script (wasm-bindgen's
// no-modules glue, loaded before it, defines wasm_bindgen): it defines glviewUnpack and
// glviewStart, and the input both pages take (glviewKeyName, glviewPointer).
'use strict';

// Bytes from base64 of gzip (the pages' and the scene request's packing).
window.glviewUnpack = async function (b64) {
  const text = atob(b64);
  const bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('gzip'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
};

// A playing view's time moved on by the page's clock between two animation frames (`t`, from
// requestAnimationFrame); `clock.last` is the previous frame's (null: none yet, or paused).
window.glviewAdvance = function (viewer, t, clock) {
  if (viewer.playing()) {
    if (clock.last !== null) viewer.advance((t - clock.last) / 1000);
    clock.last = t;
  } else {
    clock.last = null;
  }
};

// Why this browser cannot draw here (null: it may try): checked before anything is fetched.
window.glviewCannot = function () {
  if (typeof WebAssembly !== 'object') return 'this browser runs no WebAssembly';
  if (typeof DecompressionStream !== 'function') {
    return 'this browser cannot unpack the renderer (no DecompressionStream)';
  }
  const probe = document.createElement('canvas');
  if (!(probe.getContext('webgl2') || probe.getContext('webgl'))) {
    return 'this browser gives the page no WebGL context (disabled, blocklisted or missing)';
  }
  return null;
};

// Starts a viewer. o: { wasm (a URL, or {b64}: packed as the pages pack files), scene: {words, files: [{path, gz}], maps, prepared (the model as scene bytes, optional)},
// webgl (1 forces WebGL 1), force (draw even on a slow context: no
// failIfMajorPerformanceCaveat, no speed rule), slowMs (the rule's bound: the median of three
// frames after the first) }. Resolves to {viewer, canvas, info, timings}, or {why}: the
// reason the page does not draw (the viewer is freed then).
window.glviewStart = async function (o) {
  const started = performance.now();
  let viewer, canvas;
  try {
    const s = o.scene;
    const packed = [s.maps, s.prepared || ''].concat(s.files.map((f) => f.gz));
    const [maps, prepared, ...files] = await Promise.all(packed.map((b) => b ? glviewUnpack(b) : null));
    const wasm = typeof o.wasm === 'string' ? o.wasm : await glviewUnpack(o.wasm.b64);
    await wasm_bindgen({ module_or_path: wasm });
    const inputs = new wasm_bindgen.Inputs();
    s.files.forEach((f, i) => inputs.file(f.path, files[i]));
    inputs.maps(maps);
    // The model as scene bytes, where the page has them instead of its files.
    if (prepared) inputs.prepared(prepared);
    inputs.refuse_slow_context(!o.force);
    canvas = document.createElement('canvas');
    viewer = wasm_bindgen.Viewer.open(canvas, s.words, o.webgl === 1 ? 1 : 2, inputs);
  } catch (e) {
    return { why: 'the renderer did not start (' + String(e && e.message || e) + ')' };
  }
  // The first frame compiles the programs; the next ones are what a drag costs.
  const timings = { ready_ms: performance.now() - started };
  try {
    viewer.draw();
    viewer.finish();
    timings.first_frame_ms = performance.now() - started;
    const frames = [];
    for (let i = 0; i < 3; i++) {
      const t = performance.now();
      viewer.draw();
      viewer.finish();
      frames.push(performance.now() - t);
    }
    frames.sort((a, b) => a - b);
    timings.frame_ms = frames[1];
  } catch (e) {
    viewer.free();
    return { why: 'the renderer failed to draw (' + String(e && e.message || e) + ')' };
  }
  if (timings.frame_ms > o.slowMs && !o.force) {
    viewer.free();
    return {
      why: 'a frame took ' + timings.frame_ms.toFixed(1) + ' ms here (over ' + o.slowMs +
        ' ms: too slow to follow a drag)',
    };
  }
  return { viewer, canvas, info: JSON.parse(viewer.info()), timings };
};

// The window's name (glview --help's key table) of a key pressed, or null for the browser's
// own shortcuts (Ctrl+R, Ctrl+-): the names differ from the browser's for these.
const GLVIEW_KEY_NAMES = {
  ArrowLeft: 'Left', ArrowRight: 'Right', ArrowUp: 'Up', ArrowDown: 'Down', '=': 'Plus',
  ' ': 'Space',
};
window.glviewKeyName = function (e) {
  if (e.ctrlKey || e.metaKey || e.altKey) return null;
  return GLVIEW_KEY_NAMES[e.key] || e.key;
};

// One pointer drags, two touching pointers pinch, the wheel zooms, on element `el`; movement
// is summed and handed on at most once per animation frame (one draw, or one message, per
// frame): on.drag(dx, dy) in whole pixels (the remainder waits for the next frame),
// on.wheel(notches) (away from the user and fingers apart zoom in; a mouse notch is 100
// pixels in Chromium and 3 lines in Firefox, a touchpad gives fractions; one notch per factor
// 1.1 of two fingers' distance).
window.glviewPointer = function (el, on) {
  const pointers = new Map(); // pointerId -> {x, y}
  let dragX = 0, dragY = 0, notches = 0, pinchDist = 0, queued = false;
  const distance = () => {
    const [a, b] = [...pointers.values()];
    return Math.hypot(a.x - b.x, a.y - b.y);
  };
  const flush = () => {
    queued = false;
    const dx = Math.round(dragX), dy = Math.round(dragY);
    if (dx || dy) {
      dragX -= dx; dragY -= dy;
      on.drag(dx, dy);
    }
    const n = Math.round(notches * 100) / 100;
    notches = 0;
    if (n) on.wheel(n);
  };
  const queue = () => {
    if (!queued) {
      queued = true;
      requestAnimationFrame(flush);
    }
  };
  const up = (e) => {
    pointers.delete(e.pointerId);
    pinchDist = pointers.size === 2 ? distance() : 0;
  };
  el.addEventListener('pointerdown', (e) => {
    if (e.pointerType === 'mouse' && e.button !== 0) return;
    el.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
    if (pointers.size === 2) pinchDist = distance();
    el.focus();
    e.preventDefault();
  });
  el.addEventListener('pointermove', (e) => {
    const p = pointers.get(e.pointerId);
    if (!p) return;
    const dx = e.clientX - p.x, dy = e.clientY - p.y;
    p.x = e.clientX; p.y = e.clientY;
    if (pointers.size === 1) {
      dragX += dx; dragY += dy;
    } else if (pointers.size === 2) {
      const d = distance();
      if (pinchDist > 0 && d > 0) notches += Math.log(d / pinchDist) / Math.log(1.1);
      pinchDist = d;
    }
    queue();
  });
  el.addEventListener('pointerup', up);
  el.addEventListener('pointercancel', up);
  el.addEventListener('wheel', (e) => {
    e.preventDefault(); // the page must not scroll
    const per = e.deltaMode === 1 ? 3 : e.deltaMode === 2 ? 1 : 100;
    notches += -e.deltaY / per;
    queue();
  }, { passive: false });
};
