// needlesim trainer: draws the live session (GET /api/frame) and sends the user's
// held keys and buttons (POST /api/drive). State for tests and tools: window.trainer.
'use strict';
(function () {
  const MM = 1000, DEG = 180 / Math.PI;
  const trainer = window.trainer = { info: null, frame: null, samples: [], punctureDepth: null, frames: 0, errors: [] };
  const $ = (id) => document.getElementById(id);
  const fmt = (v, d) => (v === null || v === undefined || !isFinite(v)) ? '–' : v.toFixed(d);

  // ---------------------------------------------------------------- controls
  const held = {};  // axis -> {source: dir}
  let sentDrive = '';
  function drive() {
    const d = { insert: 0, lateral: 0, rotate: 0, tilt: 0, roll: 0 };
    for (const axis in held) for (const src in held[axis]) d[axis] += held[axis][src];
    for (const k in d) d[k] = Math.max(-1, Math.min(1, d[k]));
    const body = JSON.stringify(d);
    if (body === sentDrive) return;
    sentDrive = body;
    post('/api/drive', body);
  }
  function hold(axis, source, dir) {
    held[axis] = held[axis] || {};
    if (dir) held[axis][source] = dir; else delete held[axis][source];
    drive();
  }
  function post(path, body) {
    return fetch(path, { method: 'POST', body: body || '{}', headers: { 'Content-Type': 'application/json' } })
      .catch((e) => trainer.errors.push(String(e)));
  }
  const keys = {
    w: ['insert', 1], arrowup: ['insert', 1], s: ['insert', -1], arrowdown: ['insert', -1],
    a: ['rotate', -1], d: ['rotate', 1], arrowleft: ['lateral', -1], arrowright: ['lateral', 1],
    q: ['roll', -1], e: ['roll', 1], r: ['tilt', 1], f: ['tilt', -1],
  };
  window.addEventListener('keydown', (ev) => {
    const k = ev.key.toLowerCase();
    if (k === 'b' && !ev.repeat) { post('/api/flip'); return; }
    if (!keys[k]) return;
    ev.preventDefault();
    hold(keys[k][0], 'key:' + k, keys[k][1]);
  });
  window.addEventListener('keyup', (ev) => {
    const k = ev.key.toLowerCase();
    if (keys[k]) hold(keys[k][0], 'key:' + k, 0);
  });
  window.addEventListener('blur', () => { for (const a in held) held[a] = {}; drive(); });
  document.querySelectorAll('button[data-axis]').forEach((b) => {
    const on = (ev) => { ev.preventDefault(); b.classList.add('held'); hold(b.dataset.axis, b.id, Number(b.dataset.dir)); };
    const off = () => { b.classList.remove('held'); hold(b.dataset.axis, b.id, 0); };
    b.addEventListener('pointerdown', on);
    b.addEventListener('pointerup', off);
    b.addEventListener('pointerleave', off);
  });
  $('btn-flip').onclick = () => post('/api/flip');
  $('btn-reset').onclick = () => post('/api/reset').then(resetPlot);
  $('btn-stop').onclick = () => post('/api/stop').then(() => { $('title').textContent += ' · stopped'; });
  $('exaggerate').oninput = (ev) => { $('exaggerate-value').textContent = ev.target.value; };

  // ---------------------------------------------------------------- 3D view
  const view = $('view');
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  view.appendChild(renderer.domElement);
  trainer.renderer = renderer;
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x14181f);
  const camera = new THREE.PerspectiveCamera(40, 1, 0.1, 5000);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  trainer.camera = camera;
  scene.add(new THREE.AmbientLight(0xffffff, 0.75));
  const sun = new THREE.DirectionalLight(0xffffff, 0.5);
  sun.position.set(0.3, -0.5, 1);
  scene.add(sun);
  let tissue = null, rest = null, needle = null;
  let solid = false;  // a 3D block (realtime3d): drawn see-through, so the needle inside shows

  function colormap(t, out, i) {  // turbo-like: blue, cyan, green, yellow, red
    const stops = [[0.19, 0.07, 0.23], [0.27, 0.53, 0.98], [0.10, 0.89, 0.71], [0.64, 0.99, 0.24], [0.98, 0.73, 0.22], [0.89, 0.27, 0.04], [0.48, 0.02, 0.01]];
    const x = Math.max(0, Math.min(1, t)) * (stops.length - 1), k = Math.min(Math.floor(x), stops.length - 2), f = x - k;
    for (let c = 0; c < 3; ++c) out[3 * i + c] = stops[k][c] + f * (stops[k + 1][c] - stops[k][c]);
  }

  function buildTissue(surface) {
    rest = Float32Array.from(surface.vertices.map((v) => v * MM));
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(rest.slice(), 3));
    g.setAttribute('color', new THREE.BufferAttribute(new Float32Array(rest.length).fill(0.3), 3));
    g.setIndex(surface.triangles);
    g.computeBoundingBox();
    const extent = new THREE.Vector3();
    g.boundingBox.getSize(extent);
    solid = extent.z > 0.05 * Math.max(extent.x, extent.y);
    const material = new THREE.MeshBasicMaterial({ vertexColors: THREE.VertexColors, side: THREE.DoubleSide });
    if (solid) Object.assign(material, { transparent: true, opacity: 0.35, depthWrite: false });
    tissue = new THREE.Mesh(g, material);
    tissue.renderOrder = 2;
    scene.add(tissue);
  }

  // The tissue's bounds in mm (the API's outline), flat ones given a little height to draw.
  function outlineBox(outline) {
    const lo = new THREE.Vector3().fromArray(outline.lo).multiplyScalar(MM);
    const hi = new THREE.Vector3().fromArray(outline.hi).multiplyScalar(MM);
    const box = new THREE.Box3(lo, hi), size = box.getSize(new THREE.Vector3());
    const flat = Math.max(size.z, 0.02 * size.x) - size.z;
    box.expandByVector(new THREE.Vector3(0, 0, 0.5 * flat));
    return box;
  }

  // The block as a box. An imported solid by its own surface as a see-through wire mesh that
  // moves with it (a smooth organ has few creases to outline); an imported plane by its rims.
  function buildOutline(outline) {
    const lines = new THREE.LineBasicMaterial({ color: 0x8090a8 });
    if (outline.kind === 'imported' && solid) {
      const wire = new THREE.MeshBasicMaterial({ color: 0x8090a8, wireframe: true, transparent: true, opacity: 0.35, depthWrite: false });
      trainer.outline = new THREE.Mesh(tissue.geometry, wire);
      trainer.outline.renderOrder = 3;
      scene.add(trainer.outline);
      return;
    }
    if (outline.kind === 'imported') {
      scene.add(trainer.outline = new THREE.LineSegments(new THREE.EdgesGeometry(tissue.geometry, 30), lines));
      return;
    }
    const box = outlineBox(outline), size = box.getSize(new THREE.Vector3());
    const edges = new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxBufferGeometry(1, 1, 1)), lines);
    edges.scale.copy(size);
    box.getCenter(edges.position);
    scene.add(trainer.outline = edges);
  }

  // The first view: the whole tissue (its bounding sphere) fills the narrower of the view's two
  // angles, seen from the entry side, in front and above.
  function frameTissue(outline) {
    const sphere = outlineBox(outline).getBoundingSphere(new THREE.Sphere());
    const half = THREE.Math.degToRad(camera.fov / 2);
    const narrower = Math.min(half, Math.atan(Math.tan(half) * camera.aspect));
    const distance = 1.05 * sphere.radius / Math.sin(narrower);
    const from = (solid ? new THREE.Vector3(-1.3, -1.6, 1.1) : new THREE.Vector3(-0.4, -1.3, 1.3)).normalize();
    controls.target.copy(sphere.center);
    camera.position.copy(sphere.center).addScaledVector(from, distance);
    camera.near = distance / 100;
    camera.far = distance * 20;
    camera.up.set(0, 0, 1);
    camera.updateProjectionMatrix();
    controls.update();
  }

  function updateTissue(field) {
    if (!tissue || !field || field.displacement.length !== rest.length) return;
    const scale = Number($('exaggerate').value) * MM;
    const pos = tissue.geometry.attributes.position.array, col = tissue.geometry.attributes.color.array;
    let top = 0;
    for (const s of field.scalar) top = Math.max(top, s);
    const range = Math.max(top, 1e-5);
    for (let i = 0; i < rest.length; ++i) pos[i] = rest[i] + scale * field.displacement[i];
    for (let i = 0; i < field.scalar.length; ++i) colormap(field.scalar[i] / range, col, i);
    tissue.geometry.attributes.position.needsUpdate = true;
    tissue.geometry.attributes.color.needsUpdate = true;
    $('legend-title').textContent = field.name + ' [mm]';
    $('legend-max').textContent = fmt(range * MM, 3);
  }

  function updateNeedle(points) {
    if (!points || points.length < 6) return;
    const v = [];
    for (let i = 0; i < points.length; i += 3) v.push(new THREE.Vector3(points[i] * MM, points[i + 1] * MM, points[i + 2] * MM + (solid ? 0 : 0.3)));
    const g = new THREE.TubeBufferGeometry(new THREE.CatmullRomCurve3(v), 64, 0.6, 8, false);
    if (!needle) {
      needle = new THREE.Mesh(g, new THREE.MeshPhongMaterial({ color: 0xd8dde6, shininess: 80 }));
      scene.add(needle);
    } else {
      needle.geometry.dispose();
      needle.geometry = g;
    }
  }

  // ---------------------------------------------------------------- inclusions
  const TARGET_COLOUR = 0xff2bd6, INCLUSION_COLOUR = 0xe8c547;
  let inclusionMeshes = [];

  // In a solid block a sphere (a vessel: a cylinder along z through the block's height); in a
  // plane the inclusion's section, a disc.
  function inclusionGeometry(inc, height) {
    const r = inc.radius * MM, z = inc.centre[2] * MM;
    if (!solid) return new THREE.CircleBufferGeometry(inc.shape === 'cylinder' ? r : Math.sqrt(Math.max(r * r - z * z, 0)), 48);
    if (inc.shape === 'cylinder') return new THREE.CylinderBufferGeometry(r, r, height, 48).rotateX(Math.PI / 2);
    return new THREE.SphereBufferGeometry(r, 48, 32);
  }

  // At its centre moved by the displacement shown (× the slider, as the tissue).
  function placeInclusion(mesh, inc, centre) {
    const shown = (c) => (inc.centre[c] + Number($('exaggerate').value) * (centre[c] - inc.centre[c])) * MM;
    mesh.position.set(shown(0), shown(1), solid ? shown(2) : 0.2);
  }

  function buildInclusions(inclusions, outline) {
    const height = (outline.hi[2] - outline.lo[2]) * MM;
    inclusionMeshes = inclusions.map((inc) => {
      const colour = inc.target ? TARGET_COLOUR : INCLUSION_COLOUR;
      // see-through enough that the needle shows inside it; drawn before the tissue around it
      const material = new THREE.MeshPhongMaterial({ color: colour, emissive: colour, emissiveIntensity: 0.4, shininess: 30,
        specular: 0x333333, side: THREE.DoubleSide, transparent: true, opacity: 0.85, depthWrite: false });
      const mesh = new THREE.Mesh(inclusionGeometry(inc, height), material);
      mesh.renderOrder = 1;
      placeInclusion(mesh, inc, inc.centre);
      scene.add(mesh);
      return mesh;
    });
    listInclusions(inclusions);
  }

  // Under the legend: each inclusion's colour and name (as text: names come from the scenario).
  function listInclusions(inclusions) {
    $('inclusions').innerHTML = '';
    for (const inc of inclusions) {
      const row = document.createElement('div'), swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.background = '#' + (inc.target ? TARGET_COLOUR : INCLUSION_COLOUR).toString(16).padStart(6, '0');
      row.append(swatch, inc.name + (inc.target ? ' (target)' : ''));
      $('inclusions').appendChild(row);
    }
  }

  function updateInclusions(readouts) {
    const inclusions = trainer.info.inclusions;
    if (!readouts || readouts.length !== inclusions.length) return;
    readouts.forEach((r, i) => placeInclusion(inclusionMeshes[i], inclusions[i], r.centre));
  }

  // The first target's miss distance: from the tip to its displaced centre, and off the axis.
  function showTargeting(readouts) {
    const t = trainer.info.inclusions.findIndex((inc) => inc.target);
    if (t < 0 || !readouts || !readouts[t]) return;
    $('miss-label').textContent = 'miss to ' + trainer.info.inclusions[t].name;
    const mm = (v) => (v === null ? '–' : fmt(v * MM, 2) + ' mm');
    $('miss').textContent = mm(readouts[t].miss);
    $('off-axis').textContent = mm(readouts[t].missFromAxis);
  }

  function resize() {
    const w = view.clientWidth, h = view.clientHeight;
    renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(h, 1);
    camera.updateProjectionMatrix();
  }
  window.addEventListener('resize', resize);

  // ---------------------------------------------------------------- force plot
  const chart = new Chart($('chart'), {
    type: 'scatter',
    data: { datasets: [
      { label: 'axial force [N]', data: [], showLine: true, borderColor: '#2357c6', backgroundColor: '#2357c6', pointRadius: 0, borderWidth: 2, order: 2 },
      { label: 'friction [N]', data: [], showLine: true, borderColor: '#e07b00', backgroundColor: '#e07b00', pointRadius: 0, borderWidth: 1.5, borderDash: [6, 3], order: 1 },
      { label: 'puncture', data: [], pointRadius: 7, pointStyle: 'triangle', borderColor: '#d62728', backgroundColor: '#d62728', order: 0 },
    ] },
    options: { animation: false, maintainAspectRatio: false,
      scales: { x: { suggestedMin: 0, title: { display: true, text: 'depth [mm]' } }, y: { title: { display: true, text: 'force [N]' } } },
      plugins: { legend: { reverse: true, labels: { boxWidth: 12 } } } },
  });
  trainer.chart = chart;
  let nextSample = 0, lastChartUpdate = 0;

  function resetPlot() {
    chart.data.datasets.forEach((d) => { d.data = []; });
    trainer.samples = [];
    trainer.punctureDepth = null;
    nextSample = 0;
    $('events').textContent = '';
    chart.update('none');
  }

  function addSamples(frame) {
    if (frame.next < nextSample) resetPlot();  // the session was reset
    for (const s of frame.samples) {
      trainer.samples.push(s);
      chart.data.datasets[0].data.push({ x: s[1] * MM, y: s[2] });
      chart.data.datasets[1].data.push({ x: s[1] * MM, y: s[3] });
    }
    for (const d of chart.data.datasets.slice(0, 2)) if (d.data.length > 30000) d.data.splice(0, d.data.length - 30000);
    nextSample = frame.next;
    if (frame.puncture !== null && trainer.punctureDepth === null) {
      trainer.punctureDepth = frame.puncture;
      let f = 0;
      for (const s of trainer.samples) if (s[6] <= 1) f = Math.max(f, s[2]);
      chart.data.datasets[2].data = [{ x: frame.puncture * MM, y: f }];
      $('events').textContent = `puncture at ${fmt(frame.puncture * MM, 2)} mm (peak ${fmt(f, 3)} N)`;
    }
    const now = performance.now();
    if (now - lastChartUpdate > 100) { chart.update('none'); lastChartUpdate = now; }
  }

  // ---------------------------------------------------------------- the loop
  function showState(frame) {
    const s = frame.state, p = frame.pose;
    $('phase').textContent = s.phase;
    $('phase').className = s.phase;
    $('depth').textContent = fmt(s.depth * MM, 2) + ' mm';
    $('axial').textContent = fmt(s.axial, 3) + ' N';
    $('friction').textContent = fmt(s.friction, 3) + ' N';
    $('lateral').textContent = fmt(s.lateral, 3) + ' N';
    $('deflection').textContent = fmt(s.deflection * MM, 3) + ' mm';
    $('rotation').textContent = fmt(p.rotation * DEG, 1) + '°';
    $('tilt-roll').textContent = `${fmt(p.tilt * DEG, 1)}° · ${fmt(p.roll * DEG, 1)}°`;
    $('rate').textContent = `${fmt(frame.rate, 0)} Hz · step ${fmt(frame.stepCost * 1e6, 0)} µs`;
  }

  async function poll() {
    try {
      const frame = await (await fetch('/api/frame?since=' + nextSample)).json();
      trainer.frame = frame;
      trainer.frames += 1;
      addSamples(frame);
      showState(frame);
      updateTissue(frame.field);
      updateNeedle(frame.needle);
      updateInclusions(frame.inclusions);
      showTargeting(frame.inclusions);
      setTimeout(poll, 15);
    } catch (e) {
      trainer.errors.push(String(e));
      $('title').textContent = 'disconnected: the session has stopped';
    }
  }

  function draw() {
    controls.update();
    renderer.render(scene, camera);
    requestAnimationFrame(draw);
  }

  fetch('/api/info').then((r) => r.json()).then((info) => {
    trainer.info = info;
    $('title').textContent = `${info.scenario} · engine ${info.engine} · physics every ${info.dt * 1000} ms` +
      (info.hapticPort ? ` · haptic udp ${info.hapticPort}` : '');
    $('record').textContent = info.record ? 'recording to ' + info.record + ' (written when stopped)' : '';
    const c = info.controls;
    const allowed = { insert: true, lateral: c.lateral, rotate: c.rotation, tilt: c.tilt, roll: c.roll };
    document.querySelectorAll('button[data-axis]').forEach((b) => {
      b.disabled = !allowed[b.dataset.axis];
      if (b.disabled) b.title = `engine ${info.engine} does not take this motion`;
    });
    $('btn-flip').disabled = !c.roll;
    buildTissue(info.surface);
    buildOutline(info.outline);
    buildInclusions(info.inclusions, info.outline);
    resize();
    frameTissue(info.outline);
    draw();
    poll();
  }).catch((e) => { trainer.errors.push(String(e)); $('title').textContent = 'cannot reach the session: ' + e; });
})();
