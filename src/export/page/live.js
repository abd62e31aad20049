// glview export --live: draws the lesson with glview's own renderer (wasm, WebGL 2 or 1) where
// the browser can, else leaves the turntable's pictures (page.js) in place and says why. The
// renderer, the model's files and the environment maps are in the JSON block, gzipped and
// base64'd: unpacked with DecompressionStream, so the page still makes no request.
// ?glview=images shows the pictures; ?glview=live draws even on a slow (software) context;
// ?webgl=1 forces WebGL 1; ?slow-ms=N sets the speed rule's bound (the tests' way to a slow
// machine). What happened is on #view: data-mode ("live", "images",
// "starting"), data-why; window.glviewLive holds the viewer while it draws.
(async function () {
  'use strict';
  const data = JSON.parse(document.getElementById('glview-data').textContent);
  const live = data.live;
  const $ = (id) => document.getElementById(id);
  const view = $('view'), mode = $('mode');
  const query = new URLSearchParams(location.search);
  const ask = query.get('glview');
  const NY = data.yaws.length, YAW_STEP = 360 / NY;

  function images(why) {
    view.setAttribute('data-mode', 'images');
    view.setAttribute('data-why', why);
    mode.textContent = live.only
      ? 'This page draws the model in the browser, and cannot here: ' + why + '.'
      : 'Pre-rendered views (' + NY + ' directions): ' + why + '.';
  }

  if (ask === 'images') return images('asked for by the address (?glview=images)');
  const cannot = glviewCannot();
  if (cannot) return images(cannot);
  view.setAttribute('data-mode', 'starting');
  mode.textContent = 'Starting the renderer…';
  const slowMs = query.has('slow-ms') ? Number(query.get('slow-ms')) : live.slowFrameMs;
  const started = await glviewStart({
    wasm: { b64: live.wasm }, scene: live, webgl: query.get('webgl') === '1' ? 1 : 2,
    force: ask === 'live', slowMs,
  });
  if (started.why) return images(started.why);
  const { viewer, canvas, info, timings } = started;
  canvas.id = 'live-canvas';

  // Drawing: the canvas takes the first pane's place and the controls.
  const [w, h] = data.size;
  const frameA = $('pic-a').parentNode;
  $('pic-a').hidden = true;
  $('pic-b').hidden = true;
  $('pane-b').hidden = true;
  frameA.appendChild(canvas);
  window.glviewLive = { viewer, info, timings };
  view.setAttribute('data-mode', 'live');
  view.setAttribute('data-why', '');
  mode.textContent = 'Drawn live in this browser: ' + info.version + ', ' + info.dialect +
    ' (first frame ' + timings.first_frame_ms.toFixed(0) + ' ms, then ' +
    timings.frame_ms.toFixed(0) + ' ms a frame).';
  $('numbers').hidden = true;

  // The compare's numbers over the model's pixels, measured on this page's pictures by the
  // renderer (`--diff phong,pbr`'s "model" figures: the same code).
  function showNumbers() {
    const on = viewer.compare();
    $('numbers').hidden = !on;
    if (!on) return;
    const m = JSON.parse(viewer.compare_numbers());
    window.glviewLive.numbers = m;
    $('n-mean').textContent = m ? m.mean.toFixed(2) + '/255' : '–';
    $('n-p99').textContent = m ? m.p99.toFixed(0) + '/255' : '–';
    $('n-over').textContent = m ? (100 * m.over_8).toFixed(1) + ' % of ' + m.pixels +
      ' pixels (measured in this browser)' : '–';
  }

  let column = 0, pending = false, numbersTimer = 0;
  function columnOf(yaw) {
    return Math.round((yaw - data.yaws[0]) / YAW_STEP);
  }
  // Every column between the last one seen and this one (a fast drag skips none).
  function record() {
    const c = columnOf(viewer.yaw());
    const tier = viewer.compare() ? 'both' : viewer.shading() === 'pbr' ? 'pbr' : 'phong';
    const step = Math.sign(c - column);
    for (let k = column; k !== c; k += step) window.glviewLesson.visit(k, tier);
    window.glviewLesson.visit(c, tier);
    column = c;
  }
  function show() {
    const compare = viewer.compare();
    const width = compare ? 2 * w : w;
    if (canvas.width !== width) viewer.resize(width, h);
    viewer.draw();
    $('label-a').textContent = compare ? 'Phong | PBR' : viewer.shading() === 'pbr' ? 'PBR' : 'Phong';
    view.setAttribute('data-yaw', viewer.yaw().toFixed(2));
    view.setAttribute('data-pitch', viewer.pitch().toFixed(2));
    view.setAttribute('data-tier', viewer.shading());
    view.setAttribute('data-compare', String(compare));
    const time = viewer.time();
    view.setAttribute('data-time', time === undefined ? '' : String(time));
    $('tier-phong').setAttribute('aria-pressed', String(!compare && viewer.shading() !== 'pbr'));
    $('tier-pbr').setAttribute('aria-pressed', String(!compare && viewer.shading() === 'pbr'));
    $('compare').setAttribute('aria-pressed', String(compare));
    $('where').textContent = 'yaw ' + viewer.yaw().toFixed(0) + '°, pitch ' +
      viewer.pitch().toFixed(0) + '°';
    record();
    // Measured when the drawing rests: not on every frame of a drag.
    clearTimeout(numbersTimer);
    numbersTimer = setTimeout(showNumbers, 150);
  }
  // One draw per animation frame; while the animation plays (Space), every frame, the
  // view's time moved on by the page's clock.
  const clock = { last: null };
  function redraw() {
    if (pending) return;
    pending = true;
    requestAnimationFrame((t) => {
      pending = false;
      try {
        glviewAdvance(viewer, t, clock);
        show();
        if (viewer.playing()) redraw();
      } catch (e) {
        mode.textContent = 'The renderer failed: ' + String(e && e.message || e);
      }
    });
  }
  function act(f) {
    return () => {
      f();
      redraw();
    };
  }
  $('tier-phong').onclick = act(() => viewer.set_shading('phong'));
  $('tier-pbr').onclick = act(() => viewer.set_shading('pbr'));
  $('compare').onclick = act(() => viewer.set_compare(!viewer.compare()));
  $('zoom-in').onclick = act(() => viewer.key('+'));
  $('zoom-out').onclick = act(() => viewer.key('-'));
  $('reset').onclick = act(() => viewer.key('R'));

  // The window's keys, by its names (glview --help); drags, pinches and the wheel as the
  // serve page takes them (start.js), one draw per animation frame.
  view.addEventListener('keydown', (e) => {
    const name = glviewKeyName(e);
    if (name === null) return;
    try {
      if (viewer.key(name)) redraw();
      e.preventDefault();
    } catch (err) {
      // A key the window does not have is the browser's.
    }
  });
  glviewPointer(view, {
    drag: (dx, dy) => {
      viewer.drag(dx, dy);
      redraw();
    },
    wheel: (n) => {
      viewer.wheel(n);
      redraw();
    },
  });
  show();
})();
