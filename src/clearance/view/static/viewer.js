// clearance's 3-D viewer: draws a result's motion from the JSON in #clearance-data with
// three.js (global THREE, vendored). Written by clearance.view.html; see docs/viewer.md.
// The page's state is readable through window.viewer (the tests read poses from the
// scene graph, not from the data).
(function () {
  "use strict";
  const errors = [];
  window.addEventListener("error", (ev) => errors.push(String(ev.message || ev)));
  window.addEventListener("unhandledrejection", (ev) => errors.push(String(ev.reason)));

  const D = JSON.parse(document.getElementById("clearance-data").textContent);

  function bytes(b64) {
    const s = atob(b64);
    const out = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
    return out;
  }
  const f32 = (b64) => new Float32Array(bytes(b64).buffer);
  const f64 = (b64) => new Float64Array(bytes(b64).buffer);
  const u8 = (b64) => bytes(b64);

  const time = f64(D.time);
  const NF = time.length;
  const NB = D.bodies.length;
  const runs = D.runs.map((r) => ({ ...r, poses: f32(r.poses) }));
  const primary = runs.length - 1;
  // the run the "ideal" modes show: the one named ideal, else the first other run
  let idealRun = runs.findIndex((r) => r.name === "ideal");
  if (idealRun === primary) idealRun = runs.length > 1 ? 0 : -1;
  const tracks = D.clearances.map((c) => ({
    ...c,
    e: f32(c.e),
    force: f32(c.force),
    normal: f32(c.normal),
    fn: f32(c.fn),
    contact: u8(c.contact),
  }));
  const size = D.size;
  const mag = D.magnification;

  // ---- colours -------------------------------------------------------------------
  const cmap = D.colormap.map((c) => new THREE.Color(c[0], c[1], c[2]));
  function colourOf(x) {
    const u = Math.min(Math.max(x, 0), 1) * (cmap.length - 1);
    const k = Math.min(Math.floor(u), cmap.length - 2);
    return cmap[k].clone().lerp(cmap[k + 1], u - k);
  }

  // ---- renderer, scene, camera ------------------------------------------------------
  const main = document.getElementById("main");
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setClearColor(0xf4f6f8, 1);
  main.appendChild(renderer.domElement);
  renderer.domElement.addEventListener("webglcontextlost", () => errors.push("WebGL context lost"));
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(1, -2, 3);
  scene.add(sun);

  const camera = new THREE.PerspectiveCamera(40, 1, size / 200, size * 200);
  camera.up.set(0, 0, 1);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.enableDamping = false;

  // the ground: grid in the x-y plane, world axes
  const grid = new THREE.GridHelper(2 * size, 20, 0xb0b8c0, 0xd8dde2);
  grid.rotation.x = Math.PI / 2;
  scene.add(grid);
  const axes = new THREE.AxesHelper(0.2 * size);
  scene.add(axes);

  // ---- primitives -------------------------------------------------------------------
  const Y = new THREE.Vector3(0, 1, 0);
  function material(colour, ghost) {
    if (ghost) {
      return new THREE.MeshStandardMaterial({
        color: 0x9aa5b1, transparent: true, opacity: 0.35, depthWrite: false, roughness: 0.8,
      });
    }
    return new THREE.MeshStandardMaterial({ color: colour, roughness: 0.55, metalness: 0.1 });
  }
  function primitive(p, ghost) {
    const mat = material(p.colour, ghost);
    if (p.type === "sphere") {
      const m = new THREE.Mesh(new THREE.SphereGeometry(p.radius, 24, 16), mat);
      m.position.fromArray(p.centre);
      return m;
    }
    if (p.type === "rod") {
      const a = new THREE.Vector3().fromArray(p.a);
      const b = new THREE.Vector3().fromArray(p.b);
      const d = b.clone().sub(a);
      const m = new THREE.Mesh(new THREE.CylinderGeometry(p.radius, p.radius, d.length(), 20), mat);
      m.position.copy(a).add(b).multiplyScalar(0.5);
      m.quaternion.setFromUnitVectors(Y, d.normalize());
      return m;
    }
    if (p.type === "mesh") {
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.Float32BufferAttribute(p.vertices.flat(), 3));
      g.setIndex(p.faces.flat());
      g.computeVertexNormals();
      mat.side = THREE.DoubleSide;
      const m = new THREE.Mesh(g.toNonIndexed(), mat);
      m.geometry.computeVertexNormals();
      return m;
    }
    throw new Error("unknown primitive " + p.type);
  }

  // ---- bodies of each run -------------------------------------------------------------
  const roots = runs.map((r, k) => {
    const root = new THREE.Group();
    root.name = r.name;
    const ghost = k !== primary;
    root.userData.bodies = D.bodies.map((b) => {
      const g = new THREE.Group();
      g.name = b;
      g.visible = r.present[D.bodies.indexOf(b)] !== 0; // (a body this run does not have)
      for (const p of D.shapes[b] || []) g.add(primitive(p, ghost));
      for (const p of D.glyphs[b] || []) g.add(primitive(p, ghost));
      root.add(g);
      return g;
    });
    scene.add(root);
    return root;
  });
  for (const p of D.glyphs[D.ground] || []) scene.add(primitive(p, false));

  // ---- clearance joints: socket, ball at the magnified eccentricity, force arrow --------
  function markerFrame(mk) {
    const o = mk.orientation; // columns f, g, h
    const m = new THREE.Matrix4().set(
      o[0][0], o[0][1], o[0][2], mk.position[0],
      o[1][0], o[1][1], o[1][2], mk.position[1],
      o[2][0], o[2][1], o[2][2], mk.position[2],
      0, 0, 0, 1);
    return m;
  }
  // The drawn centre of the inner part in the outer marker frame: the eccentricity
  // magnified, except the travel along the axis of a joint that slides (cylindrical,
  // prismatic: e_z is the slide position, not a clearance), which is drawn true.
  const slides = (c) => c.kind === "cylindrical" || c.kind === "prismatic";
  function drawnOffset(c, e) {
    return [mag * e[0], mag * e[1], (slides(c) ? 1 : mag) * e[2]];
  }
  // The close-up point: the eccentricity in units of the clearance; for journals and
  // sliders its transverse part only (the bearing plane, the guide's cross-section).
  function closeupPoint(c, e) {
    return [e[0] / c.c, e[1] / c.c, c.kind === "spherical" ? e[2] / c.c : 0];
  }
  function jointGlyph(c) {
    const g = new THREE.Group();
    const outer = new THREE.MeshStandardMaterial({
      color: 0x8899aa, transparent: true, opacity: 0.28, depthWrite: false, roughness: 0.3,
    });
    const inner = new THREE.MeshStandardMaterial({ color: 0xd35400, roughness: 0.35, metalness: 0.3 });
    const R = c.draw_outer;
    const r = Math.max(R - mag * c.c, 0.05 * R);
    let socket, ball;
    if (c.kind === "spherical") {
      socket = new THREE.Mesh(new THREE.SphereGeometry(R, 32, 20), outer);
      ball = new THREE.Mesh(new THREE.SphereGeometry(r, 32, 20), inner);
    } else if (c.kind === "prismatic") {
      const s = R / c.outer_radius;
      socket = new THREE.Mesh(
        new THREE.BoxGeometry(2 * R, s * c.height + 2 * mag * c.height_clearance, 1.5 * s * c.length), outer);
      ball = new THREE.Mesh(new THREE.BoxGeometry(2 * R - 2 * mag * c.c, s * c.height, s * c.length), inner);
    } else {
      const L = (c.length * R) / c.outer_radius;
      socket = new THREE.Mesh(new THREE.CylinderGeometry(R, R, L, 32, 1, true), outer);
      socket.geometry.rotateX(Math.PI / 2);
      ball = new THREE.Mesh(new THREE.CylinderGeometry(r, r, 1.2 * L, 32), inner);
      ball.geometry.rotateX(Math.PI / 2);
    }
    socket.material.side = THREE.DoubleSide;
    g.add(socket);
    g.add(ball);
    const arrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 1, 0xff0000);
    arrow.visible = false;
    g.add(arrow);
    g.matrixAutoUpdate = false;
    g.matrix.copy(markerFrame(c.outer_marker));
    g.name = "clearance:" + c.name;
    return { group: g, ball, arrow };
  }
  const bodyIndex = Object.fromEntries(D.bodies.map((b, k) => [b, k]));
  const glyphs = tracks.map((c) => {
    const gl = jointGlyph(c);
    const k = bodyIndex[c.outer_body];
    // (a socket on the ground: in the clearance run's root, which is the world frame)
    (k === undefined ? roots[primary] : roots[primary].userData.bodies[k]).add(gl.group);
    return gl;
  });

  // ---- close-up panels: the ball centre in its clearance, units of c --------------------
  const MAX_CLOSEUPS = 8; // (a browser allows ~16 WebGL contexts per page)
  if (tracks.length > MAX_CLOSEUPS) {
    const note = document.createElement("div");
    note.className = "label";
    note.textContent = "close-ups of the first " + MAX_CLOSEUPS + " of " + tracks.length + " clearance joints";
    document.getElementById("closeups").appendChild(note);
  }
  const closeups = tracks.slice(0, MAX_CLOSEUPS).map((c, j) => {
    const div = document.createElement("div");
    div.className = "closeup";
    const label = document.createElement("div");
    label.className = "label";
    div.appendChild(label);
    document.getElementById("closeups").appendChild(div);
    const r = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    r.setClearColor(0xffffff, 1);
    div.appendChild(r.domElement);
    const s = new THREE.Scene();
    s.add(new THREE.HemisphereLight(0xffffff, 0x667788, 2.0));
    const edge = new THREE.LineBasicMaterial({ color: 0x7f8c8d });
    const circle = (axis) => {
      const pts = [];
      for (let k = 0; k <= 96; k++) {
        const a = (2 * Math.PI * k) / 96, u = Math.cos(a), v = Math.sin(a);
        pts.push(...(axis === 2 ? [u, v, 0] : axis === 1 ? [v, 0, u] : [0, u, v]));
      }
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.Float32BufferAttribute(pts, 3));
      return new THREE.Line(g, edge);
    };
    if (c.kind === "spherical") {
      for (const axis of [0, 1, 2]) s.add(circle(axis));
    } else if (c.kind === "prismatic") {
      const box = new THREE.BoxGeometry(2, (2 * c.height_clearance) / c.c, 0.001);
      s.add(new THREE.LineSegments(new THREE.EdgesGeometry(box), edge));
    } else {
      s.add(circle(2));
    }
    s.add(new THREE.AxesHelper(1.25));
    const trace = new THREE.BufferGeometry();
    const tp = new Float32Array(3 * NF);
    for (let k = 0; k < NF; k++) {
      const u = closeupPoint(c, c.e.subarray(3 * k, 3 * k + 3));
      tp[3 * k] = u[0];
      tp[3 * k + 1] = u[1];
      tp[3 * k + 2] = u[2];
    }
    trace.setAttribute("position", new THREE.BufferAttribute(tp, 3));
    const line = new THREE.Line(trace, new THREE.LineBasicMaterial({ color: 0x2471a3 }));
    s.add(line);
    const dot = new THREE.Mesh(new THREE.SphereGeometry(0.06, 16, 10), new THREE.MeshBasicMaterial({ color: 0xd35400 }));
    s.add(dot);
    const arrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 1, 0xff0000);
    arrow.visible = false;
    s.add(arrow);
    const cam = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
    const v = new THREE.Vector3().fromArray(c.view_direction).normalize();
    cam.up.fromArray(c.view_up);
    cam.position.copy(v.multiplyScalar(5.2));
    cam.lookAt(0, 0, 0);
    const ctl = new THREE.OrbitControls(cam, r.domElement);
    return { div, label, renderer: r, scene: s, camera: cam, controls: ctl, line, dot, arrow, track: c, index: j };
  });

  // ---- frames ---------------------------------------------------------------------------
  let frame = 0;
  const q = new THREE.Quaternion();
  const tmp = new THREE.Vector3();
  function applyFrame(k) {
    frame = Math.max(0, Math.min(NF - 1, k | 0));
    runs.forEach((r, i) => {
      const bodies = roots[i].userData.bodies;
      const o = frame * NB * 7;
      for (let b = 0; b < NB; b++) {
        const p = r.poses.subarray(o + 7 * b, o + 7 * b + 7);
        bodies[b].position.set(p[0], p[1], p[2]);
        bodies[b].quaternion.set(p[4], p[5], p[6], p[3]);
      }
    });
    tracks.forEach((c, j) => {
      const e = c.e.subarray(3 * frame, 3 * frame + 3);
      const f = c.force.subarray(3 * frame, 3 * frame + 3);
      const n = c.normal.subarray(3 * frame, 3 * frame + 3);
      const on = c.contact[frame] !== 0;
      const fn = c.fn[frame];
      const gl = glyphs[j];
      const d = drawnOffset(c, e);
      gl.ball.position.set(d[0], d[1], d[2]);
      const fl = Math.hypot(f[0], f[1], f[2]);
      const show = on && fl > 0 && showArrows;
      const colour = colourOf(c.peak > 0 ? fn / c.peak : 0);
      if (show) {
        const dir = tmp.set(f[0], f[1], f[2]).normalize();
        const L = c.arrow_length * Math.max(fn / (c.peak || 1), 0.08);
        const contact = new THREE.Vector3(n[0], n[1], n[2]).multiplyScalar(c.draw_outer);
        if (c.kind !== "spherical") contact.add(new THREE.Vector3(0, 0, d[2]));
        gl.arrow.position.copy(contact.clone().addScaledVector(dir, -L));
        gl.arrow.setDirection(dir);
        gl.arrow.setLength(L, 0.3 * L, 0.18 * L);
        gl.arrow.setColor(colour);
      }
      gl.arrow.visible = show;
      const cu = closeups[j];
      if (!cu) return; // (close-ups for the first MAX_CLOSEUPS joints only)
      cu.line.geometry.setDrawRange(0, frame + 1);
      cu.dot.position.fromArray(closeupPoint(c, e));
      const fz = c.kind === "spherical" ? f[2] : 0; // (journals, sliders: the plane's part)
      const showCu = show && Math.hypot(f[0], f[1], fz) > 0;
      if (showCu) {
        const dir = tmp.set(f[0], f[1], fz).normalize();
        const L = 0.3 + 0.9 * Math.min(fn / (c.peak || 1), 1);
        cu.arrow.position.copy(cu.dot.position).addScaledVector(dir, -L);
        cu.arrow.setDirection(dir);
        cu.arrow.setLength(L, 0.25, 0.15);
        cu.arrow.setColor(colour);
      }
      cu.arrow.visible = showCu;
      cu.label.textContent =
        c.name + " (" + c.kind + "): centre / c" + (on ? ", F_N = " + fn.toFixed(1) + " N" : ", free");
    });
    slider.value = String(frame);
    tlabel.textContent = "t = " + time[frame].toFixed(5) + " s";
    simTime = time[frame];
    dirty = true;
  }

  // ---- controls --------------------------------------------------------------------------
  const slider = document.getElementById("time");
  const tlabel = document.getElementById("tlabel");
  const playBtn = document.getElementById("play");
  const speedSel = document.getElementById("speed");
  const modeSel = document.getElementById("mode");
  const arrowsBox = document.getElementById("arrows");
  slider.max = String(NF - 1);
  let playing = false;
  let simTime = time[0];
  { // the default speed: the option nearest to the whole run in 20 s
    const want = Math.max(time[NF - 1] - time[0], 1e-9) / 20;
    let best = speedSel.options[0];
    for (const o of speedSel.options) {
      if (Math.abs(Math.log(parseFloat(o.value) / want)) < Math.abs(Math.log(parseFloat(best.value) / want))) best = o;
    }
    speedSel.value = best.value;
  }
  let speed = parseFloat(speedSel.value);
  let showArrows = arrowsBox.checked;
  let mode = idealRun >= 0 ? modeSel.value : "clearance";
  let dirty = true;
  let last = null;
  slider.addEventListener("input", () => applyFrame(parseInt(slider.value, 10)));
  playBtn.addEventListener("click", () => setPlaying(!playing));
  speedSel.addEventListener("change", () => (speed = parseFloat(speedSel.value)));
  modeSel.addEventListener("change", () => setMode(modeSel.value));
  arrowsBox.addEventListener("change", () => {
    showArrows = arrowsBox.checked;
    applyFrame(frame);
  });
  document.getElementById("prev").addEventListener("click", () => applyFrame(frame - 1));
  document.getElementById("next").addEventListener("click", () => applyFrame(frame + 1));
  document.getElementById("impact").addEventListener("click", () => {
    const onsets = tracks.flatMap((c) => c.events.filter((e) => e[1] > 0).map((e) => e[0]));
    const later = onsets.filter((t) => t > time[frame] + 1e-12).sort((a, b) => a - b);
    if (later.length) applyFrame(frameAt(later[0]) + 1);
  });
  if (idealRun < 0) modeSel.disabled = true;
  document.getElementById("mag").textContent =
    "clearance drawn \u00d7" + mag +
    (tracks.some((c) => mag * c.c > 0.95 * c.draw_outer) ? " (more than the socket: inner parts shrunk)" : "");

  function setPlaying(on) {
    playing = on;
    last = null;
    if (playing && frame >= NF - 1) applyFrame(0);
    playBtn.textContent = playing ? "\u275a\u275a pause" : "\u25b6 play";
  }
  function setMode(m) {
    mode = idealRun >= 0 ? m : "clearance";
    modeSel.value = mode;
    dirty = true;
  }
  function frameAt(t) {
    let lo = 0, hi = NF - 1;
    if (t <= time[0]) return 0;
    if (t >= time[hi]) return hi;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (time[mid] <= t) lo = mid; else hi = mid;
    }
    return lo;
  }

  // impact ticks under the slider: onsets of every clearance joint
  function drawTicks() {
    const cv = document.getElementById("ticks");
    const w = (cv.width = cv.clientWidth);
    const h = (cv.height = cv.clientHeight);
    const ctx = cv.getContext("2d");
    ctx.clearRect(0, 0, w, h);
    tracks.forEach((c, j) => {
      ctx.fillStyle = ["#c0392b", "#8e44ad", "#16a085", "#d35400", "#2c3e50"][j % 5];
      for (const e of c.events) {
        if (e[1] <= 0) continue;
        ctx.fillRect((frameAt(e[0]) / Math.max(NF - 1, 1)) * (w - 1), 0, 1, h); // (slider: frames)
      }
    });
  }

  // ---- camera ---------------------------------------------------------------------------
  function frameCamera() {
    const box = new THREE.Box3();
    roots[primary].userData.bodies.forEach((g) => box.expandByObject(g));
    const c = box.getCenter(new THREE.Vector3());
    controls.target.copy(c);
    camera.position.copy(c).add(new THREE.Vector3(1.4, -1.9, 0.9).multiplyScalar(size));
    controls.update();
  }
  function resize() {
    const w = main.clientWidth, h = main.clientHeight;
    renderer.setSize(w, h, false);
    renderer.domElement.style.width = w + "px";
    renderer.domElement.style.height = h + "px";
    for (const cu of closeups) {
      const s = cu.div.clientWidth;
      cu.renderer.setSize(s, s);
    }
    drawTicks();
    dirty = true;
  }
  window.addEventListener("resize", resize);

  // ---- drawing ----------------------------------------------------------------------------
  let renders = 0;
  function render() {
    const w = main.clientWidth, h = main.clientHeight;
    const show = (k) => roots.forEach((r, i) => (r.visible = k === "all" || k === i));
    glyphs.forEach((g) => (g.group.visible = mode !== "ideal"));
    renderer.setScissorTest(mode === "side");
    if (mode === "side" && idealRun >= 0) {
      camera.aspect = w / 2 / h;
      camera.updateProjectionMatrix();
      for (const [i, x] of [[idealRun, 0], [primary, w / 2]]) {
        show(i);
        renderer.setViewport(x, 0, w / 2, h);
        renderer.setScissor(x, 0, w / 2, h);
        renderer.render(scene, camera);
      }
    } else {
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
      show(mode === "overlay" ? "all" : mode === "ideal" ? idealRun : primary);
      renderer.setViewport(0, 0, w, h);
      renderer.render(scene, camera);
    }
    for (const cu of closeups) {
      cu.controls.update();
      cu.renderer.render(cu.scene, cu.camera);
    }
    renders++;
  }
  function tick(now) {
    if (playing) {
      if (last !== null) {
        simTime += ((now - last) / 1000) * speed;
        const k = frameAt(simTime);
        if (simTime >= time[NF - 1]) {
          applyFrame(NF - 1);
          setPlaying(false);
        } else if (k !== frame) {
          const keep = simTime;
          applyFrame(k);
          simTime = keep;
        }
      }
      last = now;
    }
    if (dirty) render();
    dirty = false;
    requestAnimationFrame(tick);
  }
  controls.addEventListener("change", () => (dirty = true));
  closeups.forEach((cu) => cu.controls.addEventListener("change", () => (dirty = true)));

  // ---- the page's state, for users' scripts and the tests -----------------------------------
  const wp = new THREE.Vector3();
  window.viewer = {
    ready: false,
    errors,
    frames: NF,
    runs: runs.map((r) => r.name),
    bodies: D.bodies.slice(),
    magnification: mag,
    get frame() { return frame; },
    get time() { return time[frame]; },
    get playing() { return playing; },
    get renders() { return renders; },
    get mode() { return mode; },
    frameTime: (k) => time[k],
    setFrame: (k) => { applyFrame(k); render(); return frame; },
    setMode: (m) => { setMode(m); render(); return mode; },
    play: () => setPlaying(true),
    pause: () => setPlaying(false),
    // world pose of a body as drawn: [x, y, z], [e0, e1, e2, e3]
    pose(run, body) {
      const g = roots[runs.findIndex((r) => r.name === run)].userData.bodies[bodyIndex[body]];
      g.updateWorldMatrix(true, false);
      g.getWorldPosition(wp);
      g.getWorldQuaternion(q);
      return { position: [wp.x, wp.y, wp.z], euler: [q.w, q.x, q.y, q.z] };
    },
    // the drawn ball centre of a clearance joint, in the outer marker frame [m, magnified]
    ball(name) {
      const j = tracks.findIndex((c) => c.name === name);
      return glyphs[j].ball.position.toArray();
    },
    // how a clearance joint is drawn: kind and drawn socket radius [m]
    clearance(name) {
      const c = tracks.find((x) => x.name === name);
      return { kind: c.kind, socketRadius: c.draw_outer, magnification: mag };
    },
    // the drawn force arrow of a clearance joint (outer marker frame): its tail, unit
    // direction, length and head (= tail + length * direction, the contact point)
    arrow(name) {
      const a = glyphs[tracks.findIndex((c) => c.name === name)].arrow;
      const dir = new THREE.Vector3(0, 1, 0).applyQuaternion(a.quaternion);
      const len = a.line.scale.y + a.cone.scale.y;
      return {
        visible: a.visible,
        colour: "#" + a.line.material.color.getHexString(),
        tail: a.position.toArray(),
        direction: dir.toArray(),
        length: len,
        head: a.position.clone().addScaledVector(dir, len).toArray(),
      };
    },
    visible(run, body) {
      return roots[runs.findIndex((r) => r.name === run)].userData.bodies[bodyIndex[body]].visible;
    },
    setVisible(run, body, on) {
      const i = runs.findIndex((r) => r.name === run);
      roots[i].userData.bodies[bodyIndex[body]].visible = !!on;
      render();
    },
    setCamera(position, target, fov) {
      camera.position.fromArray(position);
      controls.target.fromArray(target);
      if (fov) camera.fov = fov;
      controls.update();
      render();
      return { width: main.clientWidth, height: main.clientHeight };
    },
    canvasRect() {
      const r = renderer.domElement.getBoundingClientRect();
      return { left: r.left, top: r.top, width: r.width, height: r.height };
    },
  };

  resize();
  frameCamera();
  applyFrame(0);
  render();
  setMode(mode);
  window.viewer.ready = true;
  document.body.dataset.ready = "1";
  requestAnimationFrame(tick);
})();
