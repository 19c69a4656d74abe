// The mbstream-viewer --web page: draws the scene the viewer sends (its meshes, once per
// model) posed by each frame's matrices; probes as markers, computed from this page's own
// scene graph. State for tests in window.mbstream.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const state = window.mbstream = {
  connected: false, scene: 0, title: '', run: '', state: '', mode: '', seq: -1, t: 0,
  frames: 0, missed: 0, viewer_frames: 0, viewer_missed: 0, probes: [], readout: [],
  ghost_distance: null, rendered: 0, latency_ms: [], scene_bytes: 0, frame_bytes: 0,
  record: null,  // a test sets [] to get {seq, t, probes} of every frame drawn from then on
  denied: null,  // {status, message} when the viewer refused this page's token
  // False when this page's token may watch but not steer the replay (every page's and the
  // viewer window's: the server's run role); `controls_message` says why.
  controls: true, controls_message: '', control_refused: 0,
  // mbstream-viewer --contacts: the newest frame's contacts as drawn ({point, tip} in World,
  // m) and how many frames had any.
  contacts: [], contact_frames: 0,
};

const view = document.getElementById('view');
const hud = document.getElementById('hud');
const renderer = new THREE.WebGLRenderer({ antialias: true, alpha: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(window.innerWidth, window.innerHeight);
view.appendChild(renderer.domElement);
const world = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(30, window.innerWidth / window.innerHeight, 0.01, 1000);
camera.add(new THREE.DirectionalLight(0xffffff, 1.6));  // a headlight, as VTK's
world.add(camera);
world.add(new THREE.AmbientLight(0xffffff, 0.6));
let controls = null;

let model = null;  // { frames: [Object3D], ghost: [Object3D] | null, probes, root }
let lastNumber = 0;

const textureLoader = new THREE.TextureLoader();

function decode(base64, Type) {
  const bytes = Uint8Array.from(atob(base64), (c) => c.charCodeAt(0));
  return new Type(bytes.buffer);
}

function frameGroups(root, count) {
  const groups = [];
  for (let k = 0; k < count; ++k) {
    const group = new THREE.Group();
    group.matrixAutoUpdate = false;
    root.add(group);
    groups.push(group);
  }
  return groups;
}

function buildParts(parts, groups, root, opacity, tint) {
  for (const part of parts) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(decode(part.positions, Float32Array), 3));
    geometry.setIndex(new THREE.BufferAttribute(decode(part.indices, Uint32Array), 1));
    geometry.computeVertexNormals();
    const color = new THREE.Color(...part.color);
    if (tint) color.lerp(new THREE.Color(0.6, 0.8, 1.0), 0.3);
    const alpha = opacity * part.opacity;
    const material = new THREE.MeshPhongMaterial({
      color, transparent: alpha < 1, opacity: alpha, depthWrite: alpha >= 1, side: THREE.DoubleSide });
    if (part.uvs && part.texture_png && !tint) {  // the VTK window's image (a ghost is one tint)
      geometry.setAttribute('uv', new THREE.BufferAttribute(decode(part.uvs, Float32Array), 2));
      material.map = textureLoader.load(`data:image/png;base64,${part.texture_png}`);
      material.map.colorSpace = THREE.SRGBColorSpace;
      material.map.wrapS = material.map.wrapT = THREE.RepeatWrapping;
    }
    const mesh = new THREE.Mesh(geometry, material);
    (part.frame >= 0 ? groups[part.frame] : root).add(mesh);
  }
}

function onScene(message) {
  if (model) world.remove(model.root);
  const root = new THREE.Group();
  const frames = frameGroups(root, message.frames);
  buildParts(message.parts, frames, root, 1.0, false);
  let ghost = null;
  if (message.ghost_opacity > 0) {
    ghost = frameGroups(root, message.frames);
    buildParts(message.parts, ghost, root, message.ghost_opacity, true);
  }
  const marker = new THREE.SphereGeometry(message.probe_radius, 16, 12);
  const probes = message.probes.map((probe) => {
    const point = new THREE.Vector3(...probe.point);
    const sphere = new THREE.Mesh(marker, new THREE.MeshPhongMaterial({ color: 0xffe619, emissive: 0x665c0a }));
    sphere.position.copy(point);
    (probe.frame >= 0 ? frames[probe.frame] : root).add(sphere);
    return { name: probe.name, frame: probe.frame, refer: probe.refer, refer_name: probe.refer_name, point };
  });
  world.add(root);
  const contacts = new THREE.Group();
  root.add(contacts);
  model = { root, frames, ghost, probes, contacts, contact_marks: [], force_max: 0 };
  // The camera as the VTK viewer placed it; the mouse orbits (left), pans (right), zooms.
  const c = message.camera;
  camera.position.set(...c.position);
  camera.up.set(...c.up);
  camera.fov = c.view_angle;
  const distance = camera.position.distanceTo(new THREE.Vector3(...c.focal));
  camera.near = distance / 100;
  camera.far = distance * 100;
  camera.updateProjectionMatrix();
  if (controls) controls.dispose();
  controls = new OrbitControls(camera, renderer.domElement);
  controls.target.set(...c.focal);
  controls.update();
  state.scene = message.version;
  state.title = message.title;
  state.missing_meshes = message.missing_meshes || '';
  state.triangles = message.parts.reduce((n, p) => n + p.triangles, 0);
  state.parts = message.parts.map((p) => ({ frame: p.frame, color: p.color, opacity: p.opacity,
                                          triangles: p.triangles, textured: !!p.texture_png }));
}

function setMatrices(groups, m) {
  if (!groups || m.length !== 12 * groups.length) return false;
  groups.forEach((group, k) => {
    const a = m.slice(12 * k, 12 * k + 12);
    group.matrix.set(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8], a[9], a[10], a[11], 0, 0, 0, 1);
  });
  return true;
}

// A frame's contacts (message.c: [px, py, pz, fx, fy, fz], World, m and N), drawn as the VTK
// window draws them: a yellow point and a red arrow along the force, message.contact_scale
// m per N, or (0) 0.25 m for the largest force so far. Objects are reused frame to frame.
const kAutoLength = 0.25;
const contactPoint = new THREE.SphereGeometry(0.008, 12, 8);
const contactMaterial = new THREE.MeshPhongMaterial({ color: 0xffd91a, emissive: 0x665c0a });
function drawContacts(list) {
  const marks = model.contact_marks;
  for (const c of list) model.force_max = Math.max(model.force_max, Math.hypot(c[3], c[4], c[5]));
  const scale = state.contact_scale > 0 ? state.contact_scale
                                        : (model.force_max > 0 ? kAutoLength / model.force_max : 0);
  state.contacts = list.map((c, i) => {
    if (i >= marks.length) {
      const point = new THREE.Mesh(contactPoint, contactMaterial);
      const arrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 1, 0xf24033);
      model.contacts.add(point, arrow);
      marks.push({ point, arrow });
    }
    const origin = new THREE.Vector3(c[0], c[1], c[2]);
    const force = new THREE.Vector3(c[3], c[4], c[5]);
    const length = scale * force.length();
    marks[i].point.position.copy(origin);
    marks[i].point.visible = true;
    marks[i].arrow.position.copy(origin);
    if (length > 0) marks[i].arrow.setDirection(force.clone().normalize());
    marks[i].arrow.setLength(Math.max(length, 1e-6), 0.2 * length, 0.06 * length);
    marks[i].arrow.visible = length > 0;
    const tip = origin.clone().addScaledVector(force, scale);
    return { point: { x: origin.x, y: origin.y, z: origin.z }, tip: { x: tip.x, y: tip.y, z: tip.z } };
  });
  for (let i = list.length; i < marks.length; ++i) {
    marks[i].point.visible = false;
    marks[i].arrow.visible = false;
  }
  if (list.length > 0) state.contact_frames += 1;
}

function onFrame(message) {
  if (!model || message.scene !== state.scene) return;
  if (!setMatrices(model.frames, message.m)) return;
  setMatrices(model.ghost, message.g);
  if (message.run !== state.run) { state.frames = 0; state.missed = 0; }
  if (lastNumber && message.n > lastNumber + 1) state.missed += message.n - lastNumber - 1;
  lastNumber = message.n;
  state.frames += 1;
  Object.assign(state, {
    run: message.run, state: message.state, mode: message.mode, seq: message.seq, t: message.t,
    viewer_frames: message.frames, viewer_missed: message.missed, paused: message.paused,
    speed: message.speed, run_frames: message.run_frames, compare: message.compare,
    readout: message.probes,
    ghost_distance: message.compare ? message.tcp_distance : null,
    ghost_distance_max: message.compare ? message.tcp_distance_max : null,
  });
  if (message.c) {
    state.contact_scale = message.contact_scale;
    drawContacts(message.c);
  }
  const latency = performance.timeOrigin + performance.now() - message.posed_ms;
  state.latency_ms.push(latency);
  if (state.latency_ms.length > 1000) state.latency_ms.shift();
  // The probes from this page's scene graph: the point times its frame's world matrix, then
  // in its refer frame (as the viewer reports it); `world` is where its marker is drawn.
  model.root.updateMatrixWorld(true);
  state.probes = model.probes.map((probe) => {
    const world = probe.point.clone();
    if (probe.frame >= 0) world.applyMatrix4(model.frames[probe.frame].matrixWorld);
    const p = world.clone();
    if (probe.refer >= 0) p.applyMatrix4(model.frames[probe.refer].matrixWorld.clone().invert());
    return { name: probe.name, frame: probe.refer_name, x: p.x, y: p.y, z: p.z,
             world: { x: world.x, y: world.y, z: world.z } };
  });
  if (state.record) state.record.push({ seq: state.seq, t: state.t, probes: state.probes, contacts: state.contacts });
  updateHud();
  updateReplay(message);
}

function updateHud() {
  const lines = [
    `run ${state.run || '-'}  ${state.state}   ${state.title}`,
    `t = ${state.t.toFixed(3)} s   frames ${state.frames} (missed ${state.missed})` +
      `   viewer frames ${state.viewer_frames} (missed ${state.viewer_missed})`,
  ];
  for (const p of state.readout) {
    lines.push(`${p.name} in ${p.frame}: ${(1e3 * p.x).toFixed(3)}, ${(1e3 * p.y).toFixed(3)}, ` +
               `${(1e3 * p.z).toFixed(3)} mm`);
  }
  if (state.mode === 'replay') {
    lines.push(`replay  ${state.paused ? 'paused' : 'playing'}  x${state.speed}  frame ${state.seq} of ${state.run_frames}`);
  }
  if (state.compare) {
    lines.push(`ghost ${state.compare}  |TCP - ghost| ${(1e3 * state.ghost_distance).toPrecision(3)} mm` +
               `  max ${(1e3 * state.ghost_distance_max).toPrecision(3)} mm`);
  }
  if (state.missing_meshes) lines.push(state.missing_meshes);
  if (state.mode === 'replay' && !state.controls) lines.push(`watching only: ${state.controls_message}`);
  if (state.denied) lines.push(`refused (${state.denied.status}): ${state.denied.message}`);
  else if (!state.connected) lines.push('disconnected: reconnecting...');
  hud.textContent = lines.join('\n');
}

// ---- Replay controls: as the VTK window's keys (space, Left, Right) and slider.
const replay = document.getElementById('replay');
const seek = document.getElementById('seek');
let socket = null;
let seeking = false;
function send(control) { if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(control)); }
function updateReplay(message) {
  replay.hidden = message.mode !== 'replay';
  for (const input of replay.querySelectorAll('button, input, select')) input.disabled = !state.controls;
  seek.max = Math.max(0, message.run_frames - 1);
  if (!seeking) seek.value = Math.max(0, message.seq);
  document.getElementById('speed').value = String(message.speed);
}
document.getElementById('play').onclick = () => send(state.paused ? { resume: true } : { pause: true });
document.getElementById('step-back').onclick = () => send({ step: -1 });
document.getElementById('step-on').onclick = () => send({ step: 1 });
document.getElementById('speed').onchange = (e) => send({ speed: Number(e.target.value) });
seek.oninput = () => { seeking = true; };
seek.onchange = () => { seeking = false; send({ seek_seq: Number(seek.value) }); };
window.addEventListener('keydown', (e) => {
  if (state.mode !== 'replay' || !state.controls) return;
  if (e.code === 'Space') send(state.paused ? { resume: true } : { pause: true });
  else if (e.code === 'ArrowLeft') send({ step: -1 });
  else if (e.code === 'ArrowRight') send({ step: 1 });
  else return;
  e.preventDefault();
});
state.send = send;

// ---- Access: the viewer checks a token with the simulation server before it sends anything.
// The token comes in the URL fragment (#token=..., never sent to a server, so never in a log)
// or from the form; it is kept for this tab only and taken off the address bar.
const TOKEN_KEY = 'mbstream-token';
const fragment = new URLSearchParams(location.hash.slice(1));
if (fragment.has('token')) {
  sessionStorage.setItem(TOKEN_KEY, fragment.get('token'));
  history.replaceState(null, '', location.pathname + location.search);
}
const login = document.getElementById('login');
let denied = false;  // wait for the form rather than reconnect
login.onsubmit = (event) => {
  event.preventDefault();
  sessionStorage.setItem(TOKEN_KEY, document.getElementById('token').value.trim());
  login.hidden = true;
  denied = false;
  if (!socket || socket.readyState === WebSocket.CLOSED) connect();
};
function onDenied(message) {
  state.denied = { status: message.status, message: message.message };
  if (message.status === 503) return;  // the check failed, not the token: try again
  denied = true;
  document.getElementById('login-why').textContent = message.message;
  login.hidden = false;
  document.getElementById('token').focus();
}

// ---- The stream: the scene once per model, then the newest frame; reconnects.
function connect() {
  socket = new WebSocket(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`);
  socket.onopen = () => {
    socket.send(JSON.stringify({ token: sessionStorage.getItem(TOKEN_KEY) || '' }));
    state.connected = true;
    lastNumber = 0;
    updateHud();
  };
  socket.onclose = () => {
    state.connected = false;
    updateHud();
    if (!denied) setTimeout(connect, 1000);
  };
  socket.onmessage = (event) => {
    const message = JSON.parse(event.data);
    if (message.type === 'scene') {
      state.denied = null;
      state.scene_bytes = event.data.length;
      onScene(message);
    } else if (message.type === 'frame') {
      state.frame_bytes = event.data.length;
      onFrame(message);
    } else if (message.type === 'denied') {
      onDenied(message);
    } else if (message.type === 'access') {
      state.controls = message.controls;
      state.controls_message = message.message;
    } else if (message.type === 'control_refused') {
      state.control_refused += 1;
      state.controls_message = message.message;
      updateHud();
    }
  };
}
connect();

window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
});
renderer.setAnimationLoop(() => {
  if (controls) controls.update();
  renderer.render(world, camera);
  if (model) state.rendered += 1;
});
