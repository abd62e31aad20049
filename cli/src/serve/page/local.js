// glview serve's local mode (docs/serve.md, "Local mode"): where the browser can draw, the
// page downloads the renderer (/web/) and the model's scene (/scene) once and draws the view
// itself; the server then sends only the view's state (each frame's header `state`, no
// picture). The page's own drags, wheel and keys are drawn at once and sent as before; the
// server's state, when it shows every input sent (or is the presenter's), is taken as it is.
// Elsewhere the stream goes on, and #mode says why (data-mode "connecting" | "stream" | "starting" |
// "local", data-why). ?glview=stream keeps the stream; ?glview=local draws even on a slow
// context; ?webgl=1 forces WebGL 1; ?slow-ms=N sets the speed rule's bound.
'use strict';

const Local = (function () {
  const SLOW_FRAME_MS = 100; // as the live lesson page's rule (docs/web.md)
  const params = new URLSearchParams(location.search);
  const ask = params.get('glview');
  const token = params.get('token') ? '?token=' + encodeURIComponent(params.get('token')) : '';
  const L = { active: false, viewer: null, canvas: null, model: null, info: null, timings: null };
  let stage = null, flat = null, pending = false, numbersTimer = 0;
  const clock = { last: null };

  // The bar says which in a word (a narrow frame keeps one line); its title and the overlay
  // say the rest.
  function mode(m, why, text) {
    const el = document.getElementById('mode');
    el.dataset.mode = m;
    el.dataset.why = why || '';
    el.textContent = m === 'local' ? 'drawn here' : m === 'stream' ? 'streamed' : 'starting…';
    el.title = text;
    L.said = text;
  }

  function stream(why) {
    L.active = false;
    mode('stream', why, 'streamed: ' + why);
  }

  function script(src) {
    return new Promise((resolve, reject) => {
      const s = document.createElement('script');
      s.src = src;
      s.onload = resolve;
      s.onerror = () => reject(new Error('cannot load ' + src));
      document.head.appendChild(s);
    });
  }

  async function scene(name) {
    const sep = token ? '&' : '?';
    const r = await fetch('/scene' + token + sep + 'model=' + encodeURIComponent(name));
    if (!r.ok) throw new Error((await r.text()).trim());
    return r.json();
  }

  // A viewer of `name` at the view's size, in place of the one before (or of the 2D canvas).
  async function open(name, size) {
    const started = await glviewStart({
      wasm: '/web/glview_web_bg.wasm' + token, scene: await scene(name),
      webgl: params.get('webgl') === '1' ? 1 : 2, force: ask === 'local',
      slowMs: params.has('slow-ms') ? Number(params.get('slow-ms')) : SLOW_FRAME_MS,
    });
    if (started.why) return started.why;
    if (L.viewer) L.viewer.free();
    if (L.canvas) L.canvas.remove();
    Object.assign(L, started, { model: name });
    L.canvas.id = 'local-view';
    L.canvas.tabIndex = 0;
    stage.insertBefore(L.canvas, flat);
    resize(size[0], size[1]);
    return null;
  }

  // Starts local mode for the hello's model; `onReady` runs once the page draws.
  async function start(hello, canvas2d, onReady) {
    flat = canvas2d;
    stage = flat.parentNode;
    if (ask === 'stream') return stream('asked for by the address (?glview=stream)');
    if (!hello.local) return stream('this server has no browser build (glview serve --web-dir)');
    const cannot = glviewCannot();
    if (cannot) return stream(cannot);
    mode('starting', '', 'starting the renderer…');
    let why;
    try {
      if (typeof wasm_bindgen === 'undefined') await script('/web/glview_web.js' + token);
      why = await open(hello.model, [flat.width, flat.height]);
    } catch (e) {
      why = 'the renderer did not start (' + String(e && e.message || e) + ')';
    }
    if (why) return stream(why);
    L.active = true;
    flat.hidden = true;
    // The events the stream's canvas had go to this one.
    window.glview.local = L;
    mode('local', '', 'drawn here: ' + L.info.version + ' (first frame ' +
      L.timings.first_frame_ms.toFixed(0) + ' ms, then ' + L.timings.frame_ms.toFixed(0) + ' ms)');
    onReady(L.canvas);
  }

  function resize(w, h) {
    if (!L.viewer) return;
    L.viewer.resize(w, h);
    L.canvas.style.width = w + 'px';
    L.canvas.style.height = h + 'px';
    redraw();
  }

  // One draw per animation frame; while the view plays, every frame, its time moved on by
  // the page's clock.
  function redraw() {
    if (pending || !L.viewer) return;
    pending = true;
    requestAnimationFrame((t) => {
      pending = false;
      const v = L.viewer;
      try {
        glviewAdvance(v, t, clock);
        L.last_ms = v.draw();
        window.glview.drawn = (window.glview.drawn || 0) + 1;
        if (v.playing()) redraw();
        clearTimeout(numbersTimer);
        if (v.compare()) numbersTimer = setTimeout(numbers, 150);
      } catch (e) {
        mode('local', 'the renderer failed: ' + String(e && e.message || e), 'the renderer failed');
      }
    });
  }

  // The split view's numbers, measured on this page's picture (`--diff`'s "model" ones).
  function numbers() {
    if (!L.viewer || !L.viewer.compare()) return;
    const d = JSON.parse(L.viewer.compare_numbers());
    L.numbers = d;
    const p = document.getElementById('diff');
    p.hidden = !d;
    p.classList.remove('stale');
    if (d) {
      p.textContent = 'Phong vs PBR over ' + d.pixels + ' model pixels (measured here): mean ' +
        d.mean.toFixed(2) + '/255 · p99 ' + d.p99.toFixed(0) + '/255 · ' +
        (d.over_8 * 100).toFixed(2) + ' % over 8/255';
    }
  }

  // A frame's header: the view's state taken when `take` (it shows every input of this page,
  // or it is the presenter's), the model's scene fetched first when it is another.
  async function frame(h, take) {
    if (!take || !h.state) return;
    if (h.model !== L.model) {
      const why = await open(h.model, [L.canvas.width, L.canvas.height]).catch((e) => String(e));
      if (why) return mode('local', why, 'cannot draw ' + h.model + ': ' + why);
    }
    const before = L.viewer.view_json();
    L.viewer.set_view(JSON.stringify(h.state));
    if (L.viewer.view_json() !== before || L.viewer.playing()) redraw();
  }

  // The page's own input, drawn at once (the server's state confirms it).
  function input(f) {
    if (!L.active) return;
    try {
      f(L.viewer);
      redraw();
    } catch (e) {
      // A key the renderer does not take is the server's to refuse.
    }
  }

  // The picture on screen as a PNG (the browser's drawing of the view).
  function save(name) {
    L.canvas.toBlob((blob) => {
      const a = document.createElement('a');
      a.href = URL.createObjectURL(blob);
      a.download = name;
      document.body.appendChild(a);
      a.click();
      a.remove();
      setTimeout(() => URL.revokeObjectURL(a.href), 10000);
    }, 'image/png');
  }

  return { L, start, frame, input, resize, save, stream };
})();
