// glview serve's page: one WebSocket to the server (protocol: docs/serve.md). The server
// renders; this page only draws the frames it gets, acknowledges each one (so at most one
// is in flight) and sends input. Where the browser can draw, local.js draws the view here
// instead and the frames carry only its state (local mode). Vanilla JS, no build step.
'use strict';

const $ = (id) => document.getElementById(id);
const canvas = $('view');
const ctx = canvas.getContext('2d');
const params = new URLSearchParams(location.search);

// The token may be absent from the URL when the page came with the server's cookie; the
// socket's handshake then carries the cookie instead. The presenter's key is kept for this
// tab only (sessionStorage: a reload presents again, another tab does not).
const query = new URLSearchParams();
if (params.get('token')) query.set('token', params.get('token'));
// Storage may be refused (a frame of another site, a private window): then the key lives as
// long as the page.
const stored = (f) => { try { return f(window.sessionStorage); } catch (e) { return null; } };
const presentKey = params.get('present') || stored((s) => s.getItem('glview_present'));
if (presentKey) {
  stored((s) => s.setItem('glview_present', presentKey));
  query.set('present', presentKey);
}
// The address bar keeps neither secret (a projected presenter tab shows it): the server's
// cookie (HttpOnly) lets this page, its reloads and its socket in; the printed links still
// work for others, since the server takes the token from a link as before.
// In a frame (a course page) there is no address bar, and the cookie may not be sent: the
// address stays as it is there.
if ((params.has('token') || params.has('present')) && window.top === window.self) {
  const rest = new URLSearchParams(params);
  rest.delete('token');
  rest.delete('present');
  history.replaceState(null, '', location.pathname + (rest.toString() ? '?' + rest : '') + location.hash);
}
const wsUrl = (location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws' +
  (query.toString() ? '?' + query : '');

let ws = null;
let hello = null;
let viewW = 0, viewH = 0; // the view's size in image pixels = CSS pixels
let seq = 0;              // the last input's sequence number
let shownSeq = 0;         // the highest seq a frame has shown (frames come in order)
const sentAt = new Map(); // seq -> send time, for the round trip
let roundTrip = null;
let saveWanted = false;   // Save PNG was pressed; download the next still that is current
let overlayOn = true;
let closedWhy = '';        // the server's reason when it closes this socket

// For the browser tests (python/tests_browser) and the curious.
window.glview = {
  frames: 0, last: null, lastStill: null, sent: 0, shown: 0, errors: [],
  send: (obj) => ws.send(JSON.stringify(obj)),
};

function send(obj) {
  if (ws && ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(obj));
}

// Input that changes the view carries a seq: the frame that shows it echoes it back.
function sendInput(obj) {
  seq += 1;
  window.glview.sent = seq;
  sentAt.set(seq, performance.now());
  send(Object.assign(obj, { seq }));
}

function status(text, isError) {
  const s = $('status');
  s.textContent = text;
  s.classList.toggle('error', !!isError);
}

function setViewSize(w, h) {
  if (w === viewW && h === viewH) return;
  viewW = w; viewH = h;
  Local.resize(w, h);
  // Pixel size and CSS size equal: one image pixel per CSS pixel. Not scaled by
  // devicePixelRatio, so a still on screen is the PNG's pixels as they are.
  canvas.width = w; canvas.height = h;
  canvas.style.width = w + 'px';
  canvas.style.height = h + 'px';
}

// ---- the view fits the window (or the iframe) ----
// The view takes the room below the bar, one image pixel per CSS pixel (devicePixelRatio
// does not enter: the browser scales the canvas as it scales any CSS pixel), within the
// server's largest view (--size, `max_size`); the server is asked for that size on load and
// after a resize.

function fitSize() {
  const main = document.querySelector('main');
  const pad = parseFloat(getComputedStyle(main).paddingLeft) || 0;
  const top = $('stage').getBoundingClientRect().top + window.scrollY;
  const [maxW, maxH] = hello.max_size;
  const w = Math.floor(Math.min(maxW, document.documentElement.clientWidth - 2 * pad));
  const h = Math.floor(Math.min(maxH, window.innerHeight - top - pad));
  return [Math.max(16, w), Math.max(16, h)];
}

function fitView() {
  if (!hello || !hello.resizable) return;
  const [w, h] = fitSize();
  if (w === viewW && h === viewH) return;
  setViewSize(w, h);
  send({ type: 'size', width: w, height: h });
}

let fitTimer = 0;
window.addEventListener('resize', () => {
  clearTimeout(fitTimer);
  fitTimer = setTimeout(fitView, 150);
});

// ---- the socket ----

function connect() {
  ws = new WebSocket(wsUrl);
  ws.binaryType = 'arraybuffer';
  ws.onopen = () => status('connected');
  // A closing error (server full, idle) says why; keep it in the line.
  ws.onclose = () => status('disconnected' + (closedWhy ? ': ' + closedWhy : ''), true);
  ws.onerror = () => status('connection error', true);
  ws.onmessage = (e) => {
    if (typeof e.data === 'string') onText(JSON.parse(e.data));
    else onFrame(e.data);
  };
  // The server closes sockets silent for --idle-timeout (120 s by default).
  setInterval(() => send({ type: 'ping' }), 20000);
}

function onText(m) {
  if (m.type === 'hello') {
    hello = m;
    serverKeys.clear();
    for (const k of m.keys || []) for (const n of k.names) serverKeys.set(n.toUpperCase(), n);
    setViewSize(m.size[0], m.size[1]);
    fitView();
    fillModels(m.models, m.model);
    $('presenting').hidden = !m.presenter;
    $('follow-label').hidden = !!m.presenter;
    setPresenterOnline(m.presenter_online);
    openLink(m);
    Local.start(m, canvas, (gl) => {
      pointerEvents(gl);
      send({ type: 'local', on: true });
    });
    if (params.get('follow') === '1' && !m.presenter) $('follow').checked = true;
    if ($('follow').checked && m.presenter_online) send({ type: 'follow', on: true });
  } else if (m.type === 'presenter') {
    setPresenterOnline(m.online);
    // Following asked for before the presenter came: ask again now that there is one.
    if (m.online && $('follow').checked) send({ type: 'follow', on: true });
  } else if (m.type === 'error') {
    window.glview.errors.push(m.message);
    if (m.closing) closedWhy = m.message;
    status((m.closing ? 'closed: ' : 'error: ') + m.message, true);
  }
}

function setPresenterOnline(online) {
  $('follow').disabled = !online;
  $('follow-label').title = online ? 'show what the presenter shows' : 'no presenter online';
}

// A frame: u32 little-endian header length, the JSON header, then the JPEG or PNG bytes.
async function onFrame(buf) {
  const n = new DataView(buf).getUint32(0, true);
  const h = JSON.parse(new TextDecoder().decode(new Uint8Array(buf, 4, n)));
  const bytes = new Uint8Array(buf, 4 + n);
  const type = h.format === 'png' ? 'image/png' : 'image/jpeg';
  if (Local.L.active) {
    // Drawn here: the view's state is taken when it shows every input sent from here.
    await Local.frame(h, fromPresenter(h) || (h.seq || 0) >= seq);
    window.glview.frames += 1;
    window.glview.localFrames = (window.glview.localFrames || 0) + 1;
  } else if (bytes.length) {
    try {
      const bitmap = await createImageBitmap(new Blob([bytes], { type }));
      if (h.view) setViewSize(h.view[0], h.view[1]);
      // Interactive frames are smaller than the view: scaled up. A still is drawn 1:1.
      ctx.drawImage(bitmap, 0, 0, viewW, viewH);
      bitmap.close();
      window.glview.frames += 1;
    } catch (err) {
      status('cannot draw frame ' + h.frame + ': ' + err, true);
    }
  }
  // A presenter's frame on a follower's page carries the presenter's seq, not ours.
  if (!fromPresenter(h) && typeof h.seq === 'number' && h.seq > shownSeq) {
    shownSeq = h.seq;
    if (sentAt.has(h.seq)) roundTrip = performance.now() - sentAt.get(h.seq);
    for (const s of sentAt.keys()) if (s <= h.seq) sentAt.delete(s);
  }
  const g = window.glview;
  g.last = h;
  g.shown = shownSeq;
  if (h.still) g.lastStill = bytes.slice(); // a copy: exactly the bytes the server sent
  // Acknowledge after drawing: the server sends the next frame only then.
  send({ type: 'ack', frame: h.frame });
  if (h.still && saveWanted && stillIsCurrent()) {
    saveWanted = false;
    download();
  }
  // A follower's model is the presenter's: the picker shows the one on screen.
  if (h.model && $('model').value !== h.model) $('model').value = h.model;
  // A frame older than this page's last input must not undo a choice just made.
  if (fromPresenter(h) || shownSeq >= seq) {
    showViews(h.views);
    showMotion(h.motion);
    showStereo(h.stereo);
  }
  showOverlay(h, bytes.length);
  showDiff(h);
}

// ---- the model picker, buttons and follow box ----

// A link may carry a model and a view, so a course page opens the model where the lesson
// needs it: `?model=sub/part.glb&yaw=40&pitch=20&distance=3.5&target=0,0.2,0&fov=45&camera=1&variant=0&keys=P,P,B`
// (the camera absolutely, as `glview --yaw --pitch --distance --target --fov` take it: no
// distance or target is the fitted view; keys of the window's table: tier, toggles, or
// camera steps). Sent once, as the user's own input would be.
let linkOpened = false;
// The state keys (not camera ones) this page sent, in order: what "Copy link" carries.
const stateKeys = [];
// Not carried as keys: the camera ones (the link has the camera absolutely), and K and V (it
// has the file's camera and variant as `camera` and `variant`, whichever way they were chosen).
// Nor the animation keys: the link has the moment as `animation` and `time` (paused).
const CAMERA_KEYS = new Set(['LEFT', 'RIGHT', 'UP', 'DOWN', 'PLUS', '+', 'PAGEUP', 'MINUS', '-',
  'PAGEDOWN', 'R', 'HOME', 'F', 'K', 'V', 'SPACE', '.', ',', 'A']);
function openLink(m) {
  if (linkOpened) return;
  linkOpened = true;
  const model = params.get('model');
  if (model && m.models.includes(model) && model !== m.model) {
    $('model').value = model;
    sendInput({ type: 'model', name: model });
  }
  const num = (k) => (params.has(k) && isFinite(Number(params.get(k))) ? Number(params.get(k)) : null);
  if (num('yaw') !== null && num('pitch') !== null) {
    const cam = { type: 'camera', yaw: num('yaw'), pitch: num('pitch') };
    if (num('distance') !== null) cam.distance = num('distance');
    if (num('fov') !== null) cam.fov = num('fov');
    const t = (params.get('target') || '').split(',').map(Number);
    if (t.length === 3 && t.every(isFinite)) cam.target = t;
    sendInput(cam);
  }
  // The file's camera and variant by index, as the pickers send them.
  for (const what of ['camera', 'variant']) {
    const i = params.get(what);
    if (i !== null && /^\d{1,4}$/.test(i)) sendInput({ type: 'pick', what, index: Number(i) });
  }
  const time = num('time');
  if (time !== null && time >= 0) {
    const msg = { type: 'time', seconds: time };
    if (/^\d{1,4}$/.test(params.get('animation') || '')) msg.animation = Number(params.get('animation'));
    sendInput(msg);
  }
  const keys = (params.get('keys') || '').split(',').filter(Boolean).slice(0, 64);
  for (const k of keys) {
    const name = serverKeys.get(k.trim().toUpperCase());
    if (name) {
      if (!CAMERA_KEYS.has(name.toUpperCase())) stateKeys.push(name);
      sendInput({ type: 'key', key: name });
    }
  }
}

// This view as a link: the model, the camera of the frame on screen absolutely, and the
// state keys sent here (at most 64); the class's token when this page was opened with it,
// never the presenter's key.
function viewLink() {
  const h = window.glview.last;
  const q = new URLSearchParams();
  if (params.get('token')) q.set('token', params.get('token'));
  if (h && h.model) q.set('model', h.model);
  const c = h && h.camera;
  if (c) {
    // The header's numbers as they are: the shortest text that reads back as the same
    // number, so the link's view is the same view to the bit.
    const r = (v) => String(v);
    q.set('yaw', r(c.yaw));
    q.set('pitch', r(c.pitch));
    if (c.distance !== null) q.set('distance', r(c.distance));
    if (c.target) q.set('target', c.target.map(r).join(','));
    q.set('fov', r(c.fov));
  }
  const v = h && h.views;
  if (v && typeof v.camera === 'number') q.set('camera', String(v.camera));
  if (v && typeof v.variant === 'number') q.set('variant', String(v.variant));
  const m = h && h.motion;
  if (m && m.time !== null && m.animation !== null) {
    q.set('animation', String(m.animation));
    q.set('time', String(m.time));
  }
  if (stateKeys.length) q.set('keys', stateKeys.slice(-64).join(','));
  return location.origin + location.pathname + '?' + q;
}
window.glview.viewLink = viewLink;

$('link').addEventListener('click', async () => {
  const link = viewLink();
  try {
    await navigator.clipboard.writeText(link);
    status('link copied');
  } catch (err) {
    window.prompt('the link to this view:', link);
  }
});

function fillModels(models, current) {
  const sel = $('model');
  sel.replaceChildren(...models.map((name) => new Option(name, name, false, name === current)));
  sel.hidden = models.length < 2;
}
$('model').addEventListener('change', (e) => {
  sendInput({ type: 'model', name: e.target.value });
  e.target.blur(); // so the keys go to the view again
});

// ---- the file's cameras and material variants (K and V cycle them) ----
// The header's `views` lists their names; a picker shows only when the file has some.
// Choosing sends the index, which the server applies as K and V apply theirs; the first
// option (value '') is the orbit camera / the file's own materials.

function fillPicker(sel, names, none, current) {
  const key = JSON.stringify(names);
  if (sel.dataset.names !== key) {
    sel.dataset.names = key;
    // As text (new Option), never as markup: the names are the file author's.
    sel.replaceChildren(new Option(none, ''), ...names.map((n, i) => new Option(n, String(i))));
  }
  sel.hidden = names.length === 0;
  const v = current === null || current === undefined ? '' : String(current);
  if (sel.value !== v) sel.value = v;
}

function showViews(v) {
  if (!v) return;
  fillPicker($('camera'), v.cameras, 'orbit camera', v.camera);
  fillPicker($('variant'), v.variants, 'own materials', v.variant);
}

for (const what of ['camera', 'variant']) {
  $(what).addEventListener('change', (e) => {
    leaveFollow();
    const index = e.target.value === '' ? null : Number(e.target.value);
    sendInput({ type: 'pick', what, index });
    e.target.blur(); // so the keys go to the view again
  });
}

// ---- stereo 3D (T cycles the modes): the picker sends the mode, the header says the
// mode drawn (a follower's is the presenter's). ----
$('stereo').addEventListener('change', (e) => {
  leaveFollow();
  sendInput({ type: 'stereo', mode: e.target.value });
  e.target.blur(); // so the keys go to the view again
});

function showStereo(mode) {
  if (typeof mode === 'string' && $('stereo').value !== mode) $('stereo').value = mode;
}

// ---- the file's animations (Space, '.', ',' and A of the key table) ----
// The header's `motion` lists them with the one shown, its time (null: the static pose) and
// whether it plays; the controls show only when the file has some.

let motionNow = null;
let scrubbing = false;

function showMotion(m) {
  motionNow = m || null;
  const box = $('motion');
  box.hidden = !m || m.animations.length === 0;
  if (box.hidden) return;
  const sel = $('animation');
  const names = m.animations.map((a, i) => a.together ? 'all together' : a.name || 'animation ' + i);
  const key = JSON.stringify(names);
  if (sel.dataset.names !== key) {
    sel.dataset.names = key;
    // As text (new Option), never as markup: the names are the file author's.
    sel.replaceChildren(...names.map((n, i) => new Option(n, String(i))));
  }
  sel.hidden = names.length < 2;
  if (m.animation !== null && sel.value !== String(m.animation)) sel.value = String(m.animation);
  const a = m.animations[m.animation] || m.animations[0];
  $('play').textContent = m.playing ? 'Pause' : 'Play';
  const slider = $('time');
  slider.max = String(a.duration > 0 ? a.duration : 0);
  if (!scrubbing) slider.value = String(m.time === null ? 0 : m.time);
  const clock = $('clock');
  clock.textContent = m.time === null ? 'static pose'
    : m.time.toFixed(2) + ' / ' + a.duration.toFixed(2) + ' s';
  // The time shown, exactly as the header has it ('' for the static pose): the text is
  // rounded for the eye, and the browser tests read this instead of parsing it.
  clock.dataset.time = m.time === null ? '' : String(m.time);
}

$('play').addEventListener('click', (e) => {
  leaveFollow();
  sendInput({ type: 'play', on: !(motionNow && motionNow.playing) });
  e.target.blur(); // so Space goes to the view again, not to the button
});
$('step-back').addEventListener('click', (e) => { key(','); e.target.blur(); });
$('step-fwd').addEventListener('click', (e) => { key('.'); e.target.blur(); });
$('time').addEventListener('input', (e) => {
  scrubbing = true;
  leaveFollow();
  sendInput({ type: 'time', seconds: Number(e.target.value) });
});
$('time').addEventListener('change', (e) => { scrubbing = false; e.target.blur(); });
$('animation').addEventListener('change', (e) => {
  leaveFollow();
  sendInput({ type: 'time', seconds: 0, animation: Number(e.target.value) });
  e.target.blur();
});

// Whether a frame is the presenter's, shown on this follower's page (the server sends the
// presenter's frames, header and all, to every follower).
function fromPresenter(h) {
  return !!(h.presenter && hello && !hello.presenter);
}

// The still on screen is current when it shows every input sent here, or is the presenter's
// while this page still follows (input here leaves follow mode at once).
function stillIsCurrent() {
  const h = window.glview.last;
  if (!h || !h.still) return false;
  return fromPresenter(h) ? $('follow').checked : shownSeq >= seq;
}

$('save').addEventListener('click', () => {
  const h = window.glview.last;
  if (Local.L.active) return Local.save('glview-' + String(h && h.model || 'scene').replace(/[^\w.-]+/g, '_') + '.png');
  if (stillIsCurrent() && window.glview.lastStill) download();
  else { saveWanted = true; send({ type: 'still' }); }
});

// The PNG exactly as the server sent it: its text chunks hold the reproducing command.
function download() {
  const h = window.glview.last;
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([window.glview.lastStill], { type: 'image/png' }));
  a.download = 'glview-' + String(h.model || 'scene').replace(/[^\w.-]+/g, '_') + '.png';
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

$('compare').addEventListener('click', () => key('C'));
$('follow').addEventListener('change', (e) => send({ type: 'follow', on: e.target.checked }));

// The server leaves follow mode on camera or state input; the box says so at once.
function leaveFollow() {
  $('follow').checked = false;
}

// ---- keys ----

// Which keys there are comes from the server (its hello message carries the table: one list
// of keys); the browser's names of them, glviewKeyName's (start.js, the live page's too).
const serverKeys = new Map(); // upper-cased key name -> the table's spelling

function key(name) {
  leaveFollow();
  Local.input((v) => v.key(name));
  if (!CAMERA_KEYS.has(name.toUpperCase())) stateKeys.push(name);
  sendInput({ type: 'key', key: name });
}

document.addEventListener('keydown', (e) => {
  // Leave the browser's own shortcuts (Ctrl+R, Ctrl+-) and the picker's keys alone.
  const browserName = glviewKeyName(e);
  if (browserName === null) return;
  if (e.target instanceof HTMLSelectElement) return;
  if (e.target instanceof HTMLInputElement && e.target.type === 'range') return;
  const name = serverKeys.get(browserName.toUpperCase());
  if (e.key === 'h' || e.key === 'H') {
    overlayOn = !overlayOn; // local only: the server's picture has no overlay
    $('overlay').hidden = !overlayOn;
    e.preventDefault();
  } else if (name) {
    key(name);
    e.preventDefault();
  }
});

// ---- pointer: one pointer drags, two touching pointers pinch (start.js's glviewPointer,
// the live page's too). Movement is handed on at most once per animation frame: the server
// draws only the latest view anyway, and fewer messages keep the socket quiet.

const pointerInput = {
  drag: (dx, dy) => {
    leaveFollow();
    Local.input((v) => v.drag(dx, dy));
    sendInput({ type: 'drag', dx, dy });
  },
  wheel: (n) => {
    leaveFollow();
    Local.input((v) => v.wheel(n));
    sendInput({ type: 'wheel', notches: n });
  },
};

// The stream's canvas has them from the start; local mode's canvas gets them when it shows.
function pointerEvents(el) {
  glviewPointer(el, pointerInput);
}
pointerEvents(canvas);

// ---- what is on screen ----

const onOff = (b) => (b ? 'on' : 'off');
const ms = (v) => (typeof v === 'number' ? v.toFixed(1) : '?');

function showOverlay(h, nbytes) {
  const t = h.ms || {};
  const kind = h.still ? 'png still' : (h.format === 'png' ? 'png' : 'jpeg') + ' preview';
  const size = h.width + '×' + h.height + (h.view && h.width !== h.view[0] ? ' of ' + h.view.join('×') : '');
  const follow = hello && hello.presenter ? 'presenting' : fromPresenter(h) ? 'yes' : 'no';
  $('overlay').textContent = [
    'model     ' + (h.model || 'built-in scene'),
    'tier      ' + h.tier + '   shadows ' + onOff(h.shadows) + '   bloom ' + onOff(h.bloom),
    'compare   ' + onOff(h.compare) + '   following ' + follow,
    'options   ' + (h.command || '–'),
    'frame     ' + ms(t.draw) + ' draw (' + ms(t.render) + ' render, ' + ms(t.read) + ' read) + ' + ms(t.encode) + ' encode ms',
    'round     ' + (roundTrip === null ? '–' : roundTrip.toFixed(0) + ' ms (input to drawn)'),
    Local.L.active
      ? 'drawn     here: ' + Local.L.info.version + ', ' + ms(Local.L.last_ms) + ' ms; the server drew ' + h.drawn + ' pictures in all'
      : 'image     ' + kind + ' ' + size + ', ' + (nbytes / 1024).toFixed(1) + ' KiB',
  ].concat(!Local.L.active && Local.L.said ? [Local.L.said] : []).concat(h.motion && h.motion.time !== null
    ? ['time      ' + h.motion.time.toFixed(3) + ' s, animation ' + h.motion.animation + (h.motion.playing ? ', playing' : ', paused')]
    : []).join('\n');
}

// The compare still's difference of Phong and PBR over the model's pixels.
// Only compare stills carry it: while compare frames move, the last numbers stay, dimmed.
function showDiff(h) {
  const p = $('diff'), d = h.diff;
  if (!h.compare) p.textContent = ''; // old numbers must not come back with the next compare
  p.hidden = p.textContent === '' && !d;
  p.classList.toggle('stale', !d);
  if (!d) return;
  const over = typeof d.model_pixels === 'number' ? ' over ' + d.model_pixels + ' model pixels' : '';
  p.textContent = 'Phong vs PBR' + over + ': mean ' +
    d.mean.toFixed(2) + '/255 · p99 ' + d.p99.toFixed(0) + '/255 · ' +
    (d.over_8 * 100).toFixed(2) + ' % over 8/255 · 1 − SSIM ' + d.one_minus_ssim.toFixed(4);
}

connect();
