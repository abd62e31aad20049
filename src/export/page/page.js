// glview export: the lesson page's script. Plain ES5, no modules and no request: it reads
// the grid and pictures from the JSON block and swaps pictures as the student turns the
// model. View v is yaw column v % yaws.length and pitch row floor(v / yaws.length); the
// current one is in #view's data-view (the browser tests read it). On a live page
// (`glview export --live`) live.js takes the controls over once it draws (window.glviewLive)
// and reports the directions and tiers seen through window.glviewLesson.
(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('glview-data').textContent);
  var NY = data.yaws.length, NP = data.pitches.length;
  var YAW_STEP = 360 / NY;
  var ZOOMS = [1, 1.25, 1.5, 2, 2.5, 3, 4];
  var $ = function (id) { return document.getElementById(id); };
  var view = $('view'), picA = $('pic-a'), picB = $('pic-b');
  var state = { yaw: 0, pitch: 0, tier: 'phong', compare: false, zoom: 0 };
  var lms = scorm();

  function reset() {
    state.yaw = data.start % NY;
    state.pitch = Math.floor(data.start / NY);
    state.zoom = 0;
  }

  function fmt(x, digits) { return x.toFixed(digits); }

  function show() {
    if (window.glviewLive) return;
    var v = state.pitch * NY + state.yaw;
    var tierA = state.compare ? 'phong' : state.tier;
    // A live-only page has no pictures: until it draws there is nothing to show.
    if (data.phong.length === 0) return;
    picA.src = data[tierA][v];
    picA.alt = (tierA === 'phong' ? 'Phong' : 'PBR') + ' view';
    $('label-a').innerHTML = tierA === 'phong' ? 'Phong' : 'PBR';
    $('pane-b').hidden = !state.compare;
    if (state.compare) {
      picB.src = data.pbr[v];
      picB.alt = 'PBR view';
    }
    var scale = 'scale(' + ZOOMS[state.zoom] + ')';
    picA.style.transform = picB.style.transform = scale;
    picA.style.webkitTransform = picB.style.webkitTransform = scale;
    view.setAttribute('data-view', String(v));
    view.setAttribute('data-yaw', String(data.yaws[state.yaw]));
    view.setAttribute('data-pitch', String(data.pitches[state.pitch]));
    view.setAttribute('data-tier', state.tier);
    view.setAttribute('data-compare', String(state.compare));
    view.setAttribute('data-zoom', String(ZOOMS[state.zoom]));
    $('tier-phong').setAttribute('aria-pressed', String(!state.compare && state.tier === 'phong'));
    $('tier-pbr').setAttribute('aria-pressed', String(!state.compare && state.tier === 'pbr'));
    $('compare').setAttribute('aria-pressed', String(state.compare));
    var where = 'yaw ' + data.yaws[state.yaw] + '°, pitch ' + data.pitches[state.pitch] + '°';
    view.setAttribute('aria-label', 'The model at ' + where + '; arrow keys or drag to turn it');
    $('where').innerHTML = where + (ZOOMS[state.zoom] > 1 ? ', picture scaled ×' + ZOOMS[state.zoom] : '');
    var n = data.numbers[v];
    $('numbers').hidden = !state.compare;
    $('n-mean').innerHTML = n ? fmt(n.mean, 2) + '/255' : '–';
    $('n-p99').innerHTML = n ? fmt(n.p99, 0) + '/255' : '–';
    $('n-over').innerHTML = n ? fmt(100 * n.over_8, 1) + ' % of ' + n.pixels + ' pixels' : '–';
    lms.visit(state.yaw, state.compare ? 'both' : state.tier);
  }

  function turn(dyaw, dpitch) {
    state.yaw = ((state.yaw + dyaw) % NY + NY) % NY;
    state.pitch = Math.max(0, Math.min(NP - 1, state.pitch + dpitch));
    show();
  }

  function zoom(d) {
    state.zoom = Math.max(0, Math.min(ZOOMS.length - 1, state.zoom + d));
    show();
  }

  // Keys as the glview window: ArrowRight increases yaw, ArrowUp increases pitch.
  view.addEventListener('keydown', function (e) {
    if (window.glviewLive) return;
    var k = e.key || e.keyIdentifier, code = e.keyCode;
    var moves = {
      ArrowRight: [1, 0], Right: [1, 0], ArrowLeft: [-1, 0], Left: [-1, 0],
      ArrowUp: [0, 1], Up: [0, 1], ArrowDown: [0, -1], Down: [0, -1]
    };
    var byCode = { 39: [1, 0], 37: [-1, 0], 38: [0, 1], 40: [0, -1] };
    var m = moves[k] || byCode[code];
    if (m) {
      turn(m[0], m[1]);
    } else if (k === '+' || k === '=') {
      zoom(1);
    } else if (k === '-') {
      zoom(-1);
    } else {
      return;
    }
    e.preventDefault();
  });

  // Drags as the window's: dragging right turns the model right (yaw decreases by
  // dragDegPerPixel per pixel), dragging down raises the eye; one view per grid step.
  var drag = null;
  function start(x, y) {
    if (window.glviewLive) return;
    drag = { x: x, y: y };
    view.className = 'dragging';
  }
  function move(x, y) {
    if (!drag) return;
    var k = data.dragDegPerPixel;
    var sy = Math.round((drag.x - x) * k / YAW_STEP);
    var pitchStep = NP > 1 ? Math.abs(data.pitches[1] - data.pitches[0]) : 1e9;
    var sp = Math.round((y - drag.y) * k / pitchStep);
    if (sy !== 0 || sp !== 0) {
      if (sy !== 0) drag.x -= sy * YAW_STEP / k;
      if (sp !== 0) drag.y += sp * pitchStep / k;
      turn(sy, sp);
    }
  }
  function end() { drag = null; view.className = ''; }
  if (window.PointerEvent) {
    view.addEventListener('pointerdown', function (e) {
      start(e.clientX, e.clientY);
      if (view.setPointerCapture) view.setPointerCapture(e.pointerId);
      view.focus();
      e.preventDefault();
    });
    view.addEventListener('pointermove', function (e) { move(e.clientX, e.clientY); });
    view.addEventListener('pointerup', end);
    view.addEventListener('pointercancel', end);
  } else {
    view.addEventListener('mousedown', function (e) { start(e.clientX, e.clientY); view.focus(); e.preventDefault(); });
    document.addEventListener('mousemove', function (e) { move(e.clientX, e.clientY); });
    document.addEventListener('mouseup', end);
    view.addEventListener('touchstart', function (e) { var t = e.touches[0]; start(t.clientX, t.clientY); e.preventDefault(); });
    view.addEventListener('touchmove', function (e) { var t = e.touches[0]; move(t.clientX, t.clientY); e.preventDefault(); });
    view.addEventListener('touchend', end);
  }
  // The wheel scales the picture (the grid has one distance): away from the user zooms in.
  view.addEventListener('wheel', function (e) {
    if (window.glviewLive) return;
    zoom(e.deltaY < 0 ? 1 : -1);
    e.preventDefault();
  });

  $('tier-phong').onclick = function () { state.tier = 'phong'; state.compare = false; show(); };
  $('tier-pbr').onclick = function () { state.tier = 'pbr'; state.compare = false; show(); };
  $('compare').onclick = function () { state.compare = !state.compare; show(); };
  $('zoom-in').onclick = function () { zoom(1); };
  $('zoom-out').onclick = function () { zoom(-1); };
  $('reset').onclick = function () { reset(); show(); };

  // SCORM 1.2: the LMS's API object is window.API in this window, a parent or the opener.
  // Progress is the yaw columns seen (at any pitch) and the tiers seen; the lesson is
  // completed once every column and both tiers were shown. Without an LMS nothing is
  // recorded and the page works the same.
  function findApi(w) {
    for (var i = 0; w && i < 8; i++) {
      try { if (w.API && w.API.LMSInitialize) return w.API; } catch (e) { return null; }
      if (w.parent === w) break;
      w = w.parent;
    }
    return null;
  }
  function scorm() {
    var api = findApi(window);
    if (!api && window.opener) api = findApi(window.opener);
    var seen = [], tiers = { phong: false, pbr: false }, done = false, count = 0;
    if (api && String(api.LMSInitialize('')) !== 'true') api = null;
    if (api) {
      var status = String(api.LMSGetValue('cmi.core.lesson_status'));
      done = status === 'completed' || status === 'passed';
      restore(String(api.LMSGetValue('cmi.suspend_data') || ''));
      if (!done) api.LMSSetValue('cmi.core.lesson_status', 'incomplete');
      api.LMSCommit('');
      var finish = function () {
        if (!api) return;
        api.LMSCommit('');
        api.LMSFinish('');
        api = null;
      };
      window.addEventListener('pagehide', finish);
      window.addEventListener('beforeunload', finish);
    }
    // cmi.suspend_data: "yaws:0110...;tiers:phong,pbr", the columns and tiers seen so far,
    // so a student who comes back goes on where they left.
    function restore(text) {
      var m = /^yaws:([01]*);tiers:([a-z,]*)$/.exec(text);
      if (!m || m[1].length !== NY) return;
      for (var i = 0; i < NY; i++) {
        if (m[1].charAt(i) === '1' && !seen[i]) { seen[i] = true; count++; }
      }
      var t = m[2].split(',');
      for (var j = 0; j < t.length; j++) if (t[j] === 'phong' || t[j] === 'pbr') tiers[t[j]] = true;
    }
    function saved() {
      var bits = '';
      for (var i = 0; i < NY; i++) bits += seen[i] ? '1' : '0';
      var t = [];
      if (tiers.phong) t.push('phong');
      if (tiers.pbr) t.push('pbr');
      return 'yaws:' + bits + ';tiers:' + t.join(',');
    }
    function report() {
      var t = (tiers.phong ? 1 : 0) + (tiers.pbr ? 1 : 0);
      $('progress').innerHTML = 'Seen: ' + count + ' of ' + NY + ' directions, ' + t + ' of 2 tiers' +
        (count === NY && t === 2 ? ' — done' : '') + (api ? ' (recorded by the course)' : '');
      view.setAttribute('data-seen', count + '/' + NY + ',' + t + '/2');
    }
    return {
      visit: function (yaw, tier) {
        if (!seen[yaw]) { seen[yaw] = true; count++; }
        if (tier === 'both') { tiers.phong = tiers.pbr = true; } else { tiers[tier] = true; }
        var complete = count === NY && tiers.phong && tiers.pbr;
        view.setAttribute('data-complete', String(complete));
        report();
        if (api) {
          api.LMSSetValue('cmi.core.lesson_location', String(state.pitch * NY + state.yaw));
          api.LMSSetValue('cmi.suspend_data', saved());
          if (complete && !done) {
            done = true;
            api.LMSSetValue('cmi.core.lesson_status', 'completed');
            api.LMSCommit('');
          }
        }
      }
    };
  }

  // What live.js reports through: yaw column `column` (0 to NY - 1) seen in `tier`
  // ('phong', 'pbr' or 'both').
  window.glviewLesson = {
    visit: function (column, tier) {
      state.yaw = ((column % NY) + NY) % NY;
      lms.visit(state.yaw, tier);
    }
  };

  reset();
  show();
})();
