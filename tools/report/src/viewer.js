// tiltfield report: the 3-D view. Reads the JSON in <script id="tf-scene-data"> (written by
// tools/report_scene.cpp), builds one three.js object per layer, and draws on demand.
// Layer kinds: mesh (quantised positions, indices, optional per-vertex values coloured by a ramp),
// line (a polyline), segments (tool axes with a value each), points (collision sites with tooltips),
// tool (the cutter body revolved from its profile, at a few poses).
import {
  AmbientLight, BufferAttribute, BufferGeometry, Box3, Color, DirectionalLight, DoubleSide, Float32BufferAttribute,
  Group, HemisphereLight, InstancedMesh, LatheGeometry, Line, LineBasicMaterial, LineSegments, Matrix4, Mesh,
  MeshBasicMaterial, MeshStandardMaterial, PerspectiveCamera, Quaternion, Raycaster, Scene, SphereGeometry, Sphere,
  Vector2, Vector3, WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import {
  BLOCK_STOPS, DEVIATION_STOPS, RAW_STOCK_COLOR, TOOL_COLORS, clearanceStops, colorAt, cssGradient,
} from './colors.js';

function bytes(b64) {
  const bin = atob(b64);
  const out = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) out[i] = bin.charCodeAt(i);
  return out.buffer;
}
const floats = (b64) => new Float32Array(bytes(b64));

function meshObject(layer) {
  const m = layer.mesh;
  const q = new Uint16Array(bytes(m.positions));
  const pos = new Float32Array(q.length);
  for (let i = 0; i < q.length; i += 3)
    for (let a = 0; a < 3; ++a) pos[i + a] = m.origin[a] + q[i + a] * m.scale[a];
  const geom = new BufferGeometry();
  geom.setAttribute('position', new BufferAttribute(pos, 3));
  const idx = m.index_bits === 16 ? new Uint16Array(bytes(m.indices)) : new Uint32Array(bytes(m.indices));
  geom.setIndex(new BufferAttribute(idx, 1));
  const material = new MeshStandardMaterial({
    color: layer.color, flatShading: true, side: DoubleSide, roughness: 0.65, metalness: 0.05,
    transparent: layer.opacity < 1, opacity: layer.opacity, depthWrite: layer.opacity >= 0.5,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
  });
  const obj = new Mesh(geom, material);
  obj.userData.values = m.values ? floats(m.values) : null;
  obj.userData.labels = m.labels ? new Uint32Array(bytes(m.labels)) : null;
  if (layer.colorings && layer.colorings.length) applyColoring(obj, layer.colorings[0]);
  return obj;
}

// A block colouring's lookups: label -> rank among the blocks that cut, line, tool.
function blockIndex(coloring) {
  if (!coloring.index) {
    const b = coloring.blocks;
    coloring.index = new Map(b.ids.map((id, k) => [id, k]));
  }
  return coloring.index;
}

// Sets c to the colour of vertex i under `coloring`.
function vertexColor(coloring, values, labels, i, c) {
  if (coloring.kind === 'deviation') {
    const [lo, hi] = coloring.range;
    const v = values[i];
    return colorAt(DEVIATION_STOPS, v < 0 ? -v / lo : v / hi, c);
  }
  const k = blockIndex(coloring).get(labels[i]);
  if (k === undefined) return c.set(RAW_STOCK_COLOR);
  if (coloring.kind === 'tool') return c.set(TOOL_COLORS[coloring.tools.indexOf(coloring.blocks.tools[k]) % TOOL_COLORS.length]);
  const n = coloring.blocks.ids.length;
  return colorAt(BLOCK_STOPS, n > 1 ? k / (n - 1) : 0.5, c);
}

function applyColoring(obj, coloring) {
  const { values, labels } = obj.userData;
  const n = obj.geometry.getAttribute('position').count;
  const col = new Float32Array(n * 3);
  const c = new Color();
  for (let i = 0; i < n; ++i) {
    vertexColor(coloring, values, labels, i, c);
    col[3 * i] = c.r;
    col[3 * i + 1] = c.g;
    col[3 * i + 2] = c.b;
  }
  obj.geometry.setAttribute('color', new BufferAttribute(col, 3));
  obj.material.vertexColors = true;
  obj.material.color.set(0xffffff);
  obj.material.needsUpdate = true;
  obj.userData.coloring = coloring;
}

// What the pointer is over on a coloured mesh: its deviation and the block that last cut there.
function meshReadout(obj, layer, vertex) {
  const { values, labels } = obj.userData;
  const parts = [];
  if (values) parts.push(`deviation ${values[vertex] >= 0 ? '+' : '\u2212'}${fmt(Math.abs(values[vertex]))} mm`);
  const blocks = (layer.colorings || []).find((c) => c.blocks);
  if (labels && blocks) {
    const k = blockIndex(blocks).get(labels[vertex]);
    parts.push(k === undefined ? 'raw stock (not cut)'
      : `block ${blocks.blocks.ids[k]}, line ${blocks.blocks.lines[k]}, tool T${blocks.blocks.tools[k]}`);
  }
  return parts.join(' \u00b7 ');
}

function lineObject(layer) {
  const geom = new BufferGeometry();
  geom.setAttribute('position', new BufferAttribute(floats(layer.positions), 3));
  return new Line(geom, new LineBasicMaterial({ color: layer.color }));
}

function segmentsObject(layer) {
  const pos = floats(layer.positions);
  const values = floats(layer.values);
  const stops = clearanceStops(layer.safety_distance, layer.value_range[1]);
  const col = new Float32Array(pos.length);
  const c = new Color();
  for (let k = 0; k < values.length; ++k) {
    colorAt(stops, values[k], c);
    col.set([c.r, c.g, c.b, c.r, c.g, c.b], 6 * k);
  }
  const geom = new BufferGeometry();
  geom.setAttribute('position', new BufferAttribute(pos, 3));
  geom.setAttribute('color', new BufferAttribute(col, 3));
  return new LineSegments(geom, new LineBasicMaterial({ vertexColors: true, transparent: true, opacity: 0.8 }));
}

function pointsObject(layer, size) {
  const pos = floats(layer.positions);
  const n = pos.length / 3;
  const mesh = new InstancedMesh(new SphereGeometry(size, 16, 12), new MeshBasicMaterial({ color: layer.color }), n);
  const m = new Matrix4();
  for (let i = 0; i < n; ++i) mesh.setMatrixAt(i, m.makeTranslation(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
  mesh.userData.titles = layer.titles;
  return mesh;
}

function toolObject(layer) {
  const group = new Group();
  const profile = layer.profile.map(([r, h]) => new Vector2(r, h));
  const geom = new LatheGeometry(profile, 48);
  const material = new MeshStandardMaterial({ color: layer.color, roughness: 0.35, metalness: 0.4, transparent: true,
                                              opacity: 0.75, side: DoubleSide });
  for (const pose of layer.poses) {
    const body = new Mesh(geom, material);
    body.quaternion.copy(new Quaternion().setFromUnitVectors(new Vector3(0, 1, 0), new Vector3(...pose.axis).normalize()));
    body.position.set(...pose.tip);
    body.userData.title = pose.label;
    group.add(body);
  }
  return group;
}

function legend(container, title, stops, ticks, format) {
  const div = document.createElement('div');
  div.className = 'legend';
  div.innerHTML = `<div class="title"></div><div class="ramp"></div><div class="ticks"></div>`;
  div.querySelector('.title').textContent = title;
  div.querySelector('.ramp').style.background = cssGradient(stops, ticks[0], ticks[ticks.length - 1]);
  for (const t of ticks) {
    const s = document.createElement('span');
    s.textContent = format(t);
    div.querySelector('.ticks').appendChild(s);
  }
  container.appendChild(div);
  return div;
}

// A legend of named colour chips.
function chipLegend(container, title, chips) {
  const div = document.createElement('div');
  div.className = 'legend';
  div.innerHTML = `<div class="title"></div><div class="chips"></div>`;
  div.querySelector('.title').textContent = title;
  for (const [text, color] of chips) {
    const s = document.createElement('span');
    s.className = 'chip';
    s.innerHTML = '<i></i>';
    s.querySelector('i').style.background = color;
    s.append(text);
    div.querySelector('.chips').appendChild(s);
  }
  container.appendChild(div);
  return div;
}

// The legend of a mesh colouring, with its note; returns its element.
function coloringLegend(container, coloring) {
  const div = coloringRamp(container, coloring);
  if (coloring.note) {
    const note = document.createElement('div');
    note.className = 'hint';
    note.textContent = coloring.note;
    div.appendChild(note);
  }
  return div;
}

function coloringRamp(container, coloring) {
  const ticks = (a, b) => [0, 1, 2, 3, 4].map((k) => a + ((b - a) * k) / 4);
  if (coloring.kind === 'deviation') {
    const [lo, hi] = coloring.range;
    return legend(container, coloring.legend, DEVIATION_STOPS.map(([t, c]) => [t < 0 ? -t * lo : t * hi, c]), ticks(lo, hi), fmt);
  }
  const b = coloring.blocks;
  if (coloring.kind === 'tool')
    return chipLegend(container, coloring.legend, [
      ...coloring.tools.map((t, k) => [`T${t}`, TOOL_COLORS[k % TOOL_COLORS.length]]), ['raw stock', RAW_STOCK_COLOR]]);
  const n = b.ids.length;
  const div = legend(container, coloring.legend, BLOCK_STOPS, ticks(0, 1), (t) => {
    if (!n) return '';
    const k = Math.round(t * (n - 1));
    return `${b.ids[k]}`;
  });
  const raw = chipLegend(div, '', [['raw stock', RAW_STOCK_COLOR]]);
  raw.className = 'legend-raw';
  div.title = n ? `blocks ${b.ids[0]} (line ${b.lines[0]}) to ${b.ids[n - 1]} (line ${b.lines[n - 1]}), coloured by their order among the ${n} blocks that shaped the stock` : '';
  return div;
}

function coloringSwatch(coloring) {
  if (coloring.kind === 'deviation') return cssGradient(DEVIATION_STOPS);
  if (coloring.kind === 'block') return cssGradient(BLOCK_STOPS);
  const n = coloring.tools.length;
  const bands = coloring.tools.map((t, k) => `${TOOL_COLORS[k % TOOL_COLORS.length]} ${(100 * k) / n}% ${(100 * (k + 1)) / n}%`);
  return `linear-gradient(to right, ${bands.join(', ')})`;
}

const fmt = (v) => (Math.abs(v) >= 10 ? v.toFixed(1) : Math.abs(v) >= 1 ? v.toFixed(2) : v.toFixed(3));

export function startViewer() {
  const host = document.getElementById('tf-viewer');
  const dataEl = document.getElementById('tf-scene-data');
  if (!host || !dataEl) return;
  const msg = host.querySelector('.viewer-msg');
  const status = (s, text) => {
    document.body.dataset.viewer = s;
    if (text !== undefined && msg) msg.textContent = text;
  };
  let renderer;
  try {
    renderer = new WebGLRenderer({ antialias: true, alpha: true, preserveDrawingBuffer: true });
  } catch (e) {
    status('no-webgl', 'The 3-D view needs WebGL, which this browser does not offer.');
    console.warn(e);
    return;
  }
  const data = JSON.parse(dataEl.textContent);
  renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
  renderer.setClearColor(0x000000, 0);
  host.appendChild(renderer.domElement);
  if (msg) msg.remove();

  const scene = new Scene();
  const camera = new PerspectiveCamera(35, 1, 0.1, 1e5);
  camera.up.set(...data.up);
  scene.add(new HemisphereLight(0xffffff, 0x8a97a8, 1.6));
  scene.add(new AmbientLight(0xffffff, 0.35));
  const key = new DirectionalLight(0xffffff, 1.9);
  key.position.set(0.4, 0.8, 1);
  camera.add(key);
  scene.add(camera);

  // Meshes first, so the bounding box (and with it the marker size) comes from the part.
  const objects = new Map();
  const box = new Box3();
  const pathBox = new Box3();
  for (const layer of data.layers) {
    let obj = null;
    if (layer.kind === 'mesh') obj = meshObject(layer);
    else if (layer.kind === 'line') obj = lineObject(layer);
    else if (layer.kind === 'segments') obj = segmentsObject(layer);
    else if (layer.kind === 'tool') obj = toolObject(layer);
    if (!obj) continue;
    obj.visible = layer.visible;
    scene.add(obj);
    objects.set(layer.id, obj);
    // The view frames the part (the meshes); axes and tool bodies may reach beyond it.
    if (layer.kind === 'mesh') box.expandByObject(obj);
    else if (layer.kind === 'line') pathBox.expandByObject(obj);
  }
  if (box.isEmpty()) box.copy(pathBox);
  if (box.isEmpty()) box.set(new Vector3(-1, -1, -1), new Vector3(1, 1, 1));
  const sphere = box.getBoundingSphere(new Sphere());
  for (const layer of data.layers)
    if (layer.kind === 'points') {
      const obj = pointsObject(layer, Math.max(sphere.radius * 0.008, 1e-3));
      obj.visible = layer.visible;
      scene.add(obj);
      objects.set(layer.id, obj);
    }

  const controls = new OrbitControls(camera, renderer.domElement);
  const home = () => {
    const dir = new Vector3(0.55, -0.85, 0.75).normalize();
    // A box's bounding sphere is loose: 0.9 of the distance that fits it still frames the part.
    const dist = sphere.radius / Math.sin((camera.fov * Math.PI) / 360) * 0.9;
    camera.position.copy(sphere.center).addScaledVector(dir, dist);
    camera.near = dist / 100;
    camera.far = dist * 10;
    camera.updateProjectionMatrix();
    controls.target.copy(sphere.center);
    controls.update();
  };
  const render = () => renderer.render(scene, camera);
  const resize = () => {
    const w = host.clientWidth || 800, h = host.clientHeight || 600;
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  };
  controls.addEventListener('change', render);
  renderer.domElement.addEventListener('dblclick', () => { home(); render(); });
  new ResizeObserver(resize).observe(host);

  // Layer switches and colour legends; a mesh with several colourings gets a choice under its switch.
  const layersEl = document.getElementById('tf-layers');
  const legendsEl = document.getElementById('tf-legends');
  const colorings = new Map();  // layer id -> function(coloring id): switches the colouring
  for (const layer of data.layers) {
    const obj = objects.get(layer.id);
    if (!obj || !layersEl) continue;
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = layer.visible;
    box.addEventListener('change', () => { obj.visible = box.checked; render(); });
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    const coloring = layer.colorings && layer.colorings[0];
    swatch.style.background = coloring ? coloringSwatch(coloring)
      : layer.value_range ? cssGradient(clearanceStops(layer.safety_distance, layer.value_range[1])) : layer.color;
    const text = document.createElement('span');
    text.textContent = layer.label;
    label.append(box, swatch, text);
    if (layer.kind === 'mesh' && layer.original_triangles > layer.mesh.triangles) {
      const tri = document.createElement('span');
      tri.className = 'tri';
      tri.title = `decimated from ${layer.original_triangles} triangles`;
      tri.textContent = `${Math.round(layer.mesh.triangles / 1000)}k\u25b3`;
      label.append(tri);
    }
    layersEl.appendChild(label);
    if (coloring && legendsEl) {
      let shown = coloringLegend(legendsEl, coloring);
      const choose = (id) => {
        const c = layer.colorings.find((x) => x.id === id);
        if (!c) return false;
        applyColoring(obj, c);
        swatch.style.background = coloringSwatch(c);
        text.textContent = text.textContent.replace(/, coloured by .*$/, `, coloured by ${c.label}`);
        const next = coloringLegend(legendsEl, c);
        legendsEl.replaceChild(next, shown);
        shown = next;
        render();
        return true;
      };
      colorings.set(layer.id, choose);
      if (layer.colorings.length > 1) {
        const select = document.createElement('select');
        select.className = 'coloring';
        select.id = `coloring-${layer.id}`;
        for (const c of layer.colorings) select.add(new Option(`colour by ${c.label}`, c.id));
        select.addEventListener('change', () => choose(select.value));
        layersEl.appendChild(select);
      }
    } else if (legendsEl && layer.value_range) {
      // Evenly spaced ticks: the labels sit where their values are on the (linear) ramp.
      const hi = layer.value_range[1];
      legend(legendsEl, layer.value_label, clearanceStops(layer.safety_distance, hi), [0, 1, 2, 3, 4].map((k) => (hi * k) / 4), fmt);
    }
  }

  // Tooltips for collision sites and tool poses, else what the pointer is over on a coloured mesh.
  const tip = document.createElement('div');
  tip.className = 'viewer-tip';
  host.appendChild(tip);
  const ray = new Raycaster();
  const readout = (ev) => {
    const r = renderer.domElement.getBoundingClientRect();
    ray.setFromCamera(new Vector2(((ev.clientX - r.left) / r.width) * 2 - 1, -((ev.clientY - r.top) / r.height) * 2 + 1), camera);
    const targets = [];
    for (const id of ['collisions', 'gouges', 'tool']) {
      const o = objects.get(id);
      if (o && o.visible) targets.push(o);
    }
    const hit = ray.intersectObjects(targets, true)[0];
    let title = null;
    if (hit) title = hit.object.userData.titles ? hit.object.userData.titles[hit.instanceId] : hit.object.userData.title;
    if (!title)
      for (const layer of data.layers) {
        const o = objects.get(layer.id);
        if (!layer.colorings || !o || !o.visible) continue;
        const h = ray.intersectObject(o, false)[0];
        if (!h) continue;
        // The face's corner nearest the hit.
        const p = o.geometry.getAttribute('position');
        let best = h.face.a, d = Infinity;
        for (const v of [h.face.a, h.face.b, h.face.c]) {
          const dv = new Vector3().fromBufferAttribute(p, v).distanceToSquared(h.point);
          if (dv < d) { d = dv; best = v; }
        }
        title = meshReadout(o, layer, best);
        break;
      }
    tip.style.display = title ? 'block' : 'none';
    if (title) {
      tip.textContent = title;
      tip.style.left = `${ev.clientX - r.left + 12}px`;
      tip.style.top = `${ev.clientY - r.top + 12}px`;
    }
    return title;
  };
  // A mesh of a few hundred thousand triangles takes a while to ray-cast: once a frame at most.
  let pending = null;
  renderer.domElement.addEventListener('pointermove', (ev) => {
    if (!pending) requestAnimationFrame(() => { readout(pending); pending = null; });
    pending = ev;
  });

  home();
  resize();
  let triangles = 0;
  for (const layer of data.layers) if (layer.kind === 'mesh') triangles += layer.mesh.triangles;
  window.tfViewer = {
    layers: data.layers.length, triangles, render,
    // For tests: the colourings of each mesh, a way to switch them, and the read-out at client (x, y).
    colorings: Object.fromEntries(data.layers.filter((l) => l.colorings).map((l) => [l.id, l.colorings.map((c) => c.id)])),
    setColoring: (layerId, id) => (colorings.has(layerId) ? colorings.get(layerId)(id) : false),
    readoutAt: (x, y) => readout({ clientX: x, clientY: y }),
  };
  status('ready');
}
