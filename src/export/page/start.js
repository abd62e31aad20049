// glview's renderer started on a canvas: what the live lesson page (glview export --live) and
// glview serve's local mode share. It checks the browser, opens a Viewer on the files given,
// draws the first frames and applies the speed rule. Classic script (wasm-bindgen's
// no-modules glue, loaded before it, defines wasm_bindgen): it defines glviewUnpack and
// glviewStart.
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

// Starts a viewer. o: { wasm (a URL, or {b64}: packed as the pages pack files), scene: {words, files: [{path, gz}], maps},
// webgl (1 forces WebGL 1), force (draw even on a slow context: no
// failIfMajorPerformanceCaveat, no speed rule), slowMs (the rule's bound: the median of three
// frames after the first) }. Resolves to {viewer, canvas, info, timings}, or {why}: the
// reason the page does not draw (the viewer is freed then).
window.glviewStart = async function (o) {
  const started = performance.now();
  let viewer, canvas;
  try {
    const s = o.scene;
    const packed = [s.maps].concat(s.files.map((f) => f.gz));
    const [maps, ...files] = await Promise.all(packed.map(glviewUnpack));
    const wasm = typeof o.wasm === 'string' ? o.wasm : await glviewUnpack(o.wasm.b64);
    await wasm_bindgen({ module_or_path: wasm });
    const inputs = new wasm_bindgen.Inputs();
    s.files.forEach((f, i) => inputs.file(f.path, files[i]));
    inputs.maps(maps);
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
