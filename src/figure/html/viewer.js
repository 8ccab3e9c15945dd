/* cairn's interactive report: the assembly (2-D as SVG, 3-D with three.js), a plan played along
 * its paths with a time slider, contacts coloured by force, the parts that start to move
 * highlighted from the onset on, and the force-time plot linked to the slider. The data is
 * CAIRN (written by cairn into the page); nothing is fetched.
 * Test hooks (used by tests/html_check.sh): #run=K&t=V1,V2,... selects a run and moves the
 * slider to each time as a user would (see the end); data-ready="1" on <body> says it has drawn. */
(function () {
  "use strict";
  const D = CAIRN;
  const SVGNS = "http://www.w3.org/2000/svg";
  const $ = (id) => document.getElementById(id);
  const dim = D.dimension;
  let run = 0; /* the run shown (a simulation, or a plan's row) */
  let time = 0;

  function el(name, attrs, parent) {
    const e = document.createElementNS(SVGNS, name);
    for (const k in attrs) e.setAttribute(k, attrs[k]);
    if (parent) parent.appendChild(e);
    return e;
  }
  function fmt(x, d) { return Number(x).toFixed(d === undefined ? 2 : d); }
  /* a contact's body: a part, a fixel (-1) or the gripper of a plan step (past the parts) */
  function bodyName(b) { return b < 0 ? "fixel" : D.parts[b] ? D.parts[b].name : "gripper"; }

  /* colours: parts by index (fixed ones grey), forces on a blue-yellow-red scale */
  const PALETTE = ["#8fb5d9", "#e6c88a", "#a9d39e", "#d9a3c7", "#9ed3d0", "#d4b59e", "#b8b0e0", "#c9d98f"];
  function partColour(i) { return D.parts[i].fixed ? "#9a9a9a" : PALETTE[i % PALETTE.length]; }
  /* force, as a fraction of the largest: light to dark blue (red is kept for what moves) */
  function forceColour(f) {
    const x = Math.max(0, Math.min(1, f));
    const r = Math.round(170 - 150 * x), g = Math.round(205 - 155 * x), b = Math.round(245 - 105 * x);
    return `rgb(${r},${g},${b})`;
  }

  /* ---- rigid motions: a pose maps x to R x + t, q = (w, x, y, z) ---- */
  function rotate(q, v) {
    const [w, x, y, z] = q;
    const tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
    return [v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)];
  }
  function apply(pose, p) {
    const v = rotate(pose.q, [p[0], p[1], p.length > 2 ? p[2] : 0]);
    return [v[0] + pose.t[0], v[1] + pose.t[1], v[2] + pose.t[2]];
  }
  const IDENTITY = { q: [1, 0, 0, 0], t: [0, 0, 0] };

  /* ---- the state at a time: which parts are there, where, which sample ---- */
  /* a page with no run (nothing to play) shows the assembly at rest */
  const EMPTY = { label: "", verdict: "", stable: false, steps: [], samples: [], t_end: 0, max_force: 1 };
  function R() { return D.runs[run] || EMPTY; }
  function sampleAt(t) {
    const S = R().samples;
    let lo = 0, hi = S.length - 1, k = -1;
    while (lo <= hi) { const m = (lo + hi) >> 1; if (S[m].t <= t + 1e-12) { k = m; lo = m + 1; } else hi = m - 1; }
    return k;
  }
  function stepAt(t) {
    const st = R().steps;
    for (let i = 0; i < st.length; i++) if (t <= st[i].t1 + 1e-12) return i;
    return st.length - 1;
  }
  /* per part: its pose, or null when it is not there (taken out by an earlier step of a
     disassembly; not yet brought in by a later step of an assembly) */
  function poses(t) {
    const P = D.parts.map(() => IDENTITY);
    const r = R(), st = r.steps, k = stepAt(t), s = sampleAt(t);
    for (let i = 0; i < st.length; i++) {
      const done = i < k || (i === k && t > st[i].t1 + 1e-12);
      if (done) { if (!r.assemble) st[i].move.forEach((p) => (P[p] = null)); }
      else if (i === k && s >= 0 && r.samples[s].step === i) {
        const smp = r.samples[s];
        st[i].move.forEach((p) => (P[p] = { q: smp.q, t: smp.p }));
      } else if (r.assemble) st[i].move.forEach((p) => (P[p] = null));
    }
    return P;
  }
  function onsetNow(t) {
    const st = R().steps, k = stepAt(t);
    const o = st[k] && st[k].onset;
    return o && t >= o.time - 1e-9 ? o : null;
  }
  const maxForce = () => Math.max(1e-300, R().max_force || 1);

  /* ---- 2-D: SVG ---- */
  let svg, gParts, gContacts, view2;
  function setup2d() {
    svg = el("svg", { id: "scene-svg" }, $("scene"));
    gParts = el("g", { transform: "scale(1,-1)" }, svg);
    gContacts = el("g", { transform: "scale(1,-1)" }, svg);
  }
  /* the 2-D view: the box of the run shown (every part, wherever its path takes it) */
  function frame2d() {
    const box = R().bounds || D.bounds;
    const w = box[1][0] - box[0][0], h = box[1][1] - box[0][1], pad = 0.06 * Math.max(w, h);
    view2 = { x: box[0][0] - pad, y: -(box[1][1] + pad), w: w + 2 * pad, h: h + 2 * pad, s: Math.max(w, h) };
    svg.setAttribute("viewBox", `${view2.x} ${view2.y} ${view2.w} ${view2.h}`);
  }
  function draw2d(t) {
    const P = poses(t), onset = onsetNow(t), moving = new Set(onset ? onset.moving : []);
    gParts.replaceChildren();
    gContacts.replaceChildren();
    const lw = view2.s / 400;
    D.parts.forEach((part, i) => {
      if (!P[i]) return;
      const fill = moving.has(i) ? "#e8574f" : partColour(i);
      part.pieces.forEach((pc) => {
        const pts = pc.verts.map((v) => apply(P[i], v));
        /* pieces split from an outline: no seams between them, the outline drawn after */
        el("polygon", {
          points: pts.map((p) => `${p[0]},${p[1]}`).join(" "),
          fill, stroke: part.outline ? fill : "#333", "stroke-width": part.outline ? lw / 2 : lw,
          "data-part": part.name, class: moving.has(i) ? "part moving" : "part",
        }, gParts);
      });
      if (part.outline) el("polygon", { points: part.outline.map((v) => apply(P[i], v)).map((p) => `${p[0]},${p[1]}`).join(" "),
        fill: "none", stroke: "#333", "stroke-width": lw }, gParts);
      const c = apply(P[i], part.label);
      const tx = el("text", { x: c[0], y: -c[1], "font-size": view2.s / 45, "text-anchor": "middle",
        "dominant-baseline": "middle", transform: "scale(1,-1)" }, gParts);
      tx.textContent = part.name;
    });
    const s = sampleAt(t);
    if (s < 0) return;
    const F = maxForce(), r = view2.s / 110;
    R().samples[s].c.forEach((c) => {
      const f = c[8] / F, col = forceColour(f);
      el("circle", { cx: c[2], cy: c[3], r: r, fill: col, stroke: "#222", "stroke-width": lw / 2 }, gContacts);
      const L = 0.12 * view2.s * f;
      if (L > 0) el("line", { x1: c[2], y1: c[3], x2: c[2] + c[5] * L, y2: c[3] + c[6] * L, stroke: col,
        "stroke-width": 2 * lw }, gContacts);
    });
  }

  /* ---- 3-D: three.js ---- */
  let three = null;
  function setup3d() {
    const host = $("scene");
    let renderer;
    try {
      renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    } catch (e) {
      host.textContent = "This browser cannot show WebGL; the 3-D view needs it.";
      return;
    }
    const W = host.clientWidth || 800, H = host.clientHeight || 520;
    renderer.setSize(W, H);
    renderer.setClearColor(0xffffff);
    host.appendChild(renderer.domElement);
    const scene = new THREE.Scene();
    scene.add(new THREE.AmbientLight(0xffffff, 0.55));
    const sun = new THREE.DirectionalLight(0xffffff, 0.6);
    const box = D.bounds, c = [0, 1, 2].map((k) => (box[0][k] + box[1][k]) / 2);
    const size = Math.max(...[0, 1, 2].map((k) => box[1][k] - box[0][k]));
    const g = D.gravity, gn = Math.hypot(g[0], g[1], g[2]) || 1, up = [-g[0] / gn, -g[1] / gn, -g[2] / gn];
    sun.position.set(c[0] + size * (up[0] + 0.5), c[1] + size * (up[1] + 0.3), c[2] + size * (up[2] + 0.8));
    scene.add(sun);
    const camera = new THREE.PerspectiveCamera(35, W / H, size / 100, size * 100);
    camera.up.set(up[0], up[1], up[2]);
    /* look from the side, a little above: a horizontal direction and up */
    let side = Math.abs(up[1]) < 0.9 ? [0, -1, 0] : [0, 0, 1];
    const d = side[0] * up[0] + side[1] * up[1] + side[2] * up[2];
    side = side.map((x, k) => x - d * up[k]);
    const sl = Math.hypot(...side);
    camera.position.set(...[0, 1, 2].map((k) => c[k] + 1.5 * size * (side[k] / sl + 0.45 * up[k] + 0.35 * (k === 0 ? 1 : 0))));
    const controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target.set(c[0], c[1], c[2]);
    controls.update();
    const objects = D.parts.map((part, i) => {
      const grp = new THREE.Group();
      part.pieces.forEach((pc) => {
        const pos = [];
        pc.faces.forEach((f) => {
          for (let k = 1; k + 1 < f.length; k++) [f[0], f[k], f[k + 1]].forEach((j) => pos.push(...pc.verts[j]));
        });
        const geo = new THREE.BufferGeometry();
        geo.setAttribute("position", new THREE.Float32BufferAttribute(pos, 3));
        geo.computeVertexNormals();
        const mat = new THREE.MeshLambertMaterial({ color: partColour(i), transparent: !part.fixed, opacity: part.fixed ? 1 : 0.92 });
        const mesh = new THREE.Mesh(geo, mat);
        grp.add(mesh);
        grp.add(new THREE.LineSegments(new THREE.EdgesGeometry(geo), new THREE.LineBasicMaterial({ color: 0x333333 })));
      });
      grp.userData.part = i;
      scene.add(grp);
      return grp;
    });
    const contacts = new THREE.Group();
    scene.add(contacts);
    three = { renderer, scene, camera, controls, objects, contacts, size };
    controls.addEventListener("change", () => renderer.render(scene, camera));
  }
  function draw3d(t) {
    if (!three) return;
    const P = poses(t), onset = onsetNow(t), moving = new Set(onset ? onset.moving : []);
    three.objects.forEach((o, i) => {
      o.visible = !!P[i];
      if (!P[i]) return;
      o.position.set(P[i].t[0], P[i].t[1], P[i].t[2]);
      o.quaternion.set(P[i].q[1], P[i].q[2], P[i].q[3], P[i].q[0]);
      o.children.forEach((m) => { if (m.isMesh) m.material.color.set(moving.has(i) ? "#e8574f" : partColour(i)); });
    });
    three.contacts.children.slice().forEach((c) => { three.contacts.remove(c); if (c.geometry) c.geometry.dispose(); });
    const s = sampleAt(t);
    if (s >= 0) {
      const F = maxForce(), r = three.size / 120;
      R().samples[s].c.forEach((c) => {
        const f = c[8] / F, col = new THREE.Color(forceColour(f));
        const dot = new THREE.Mesh(new THREE.SphereGeometry(r, 8, 6), new THREE.MeshBasicMaterial({ color: col }));
        dot.position.set(c[2], c[3], c[4]);
        three.contacts.add(dot);
        const L = 0.15 * three.size * f;
        if (L > r) three.contacts.add(new THREE.ArrowHelper(new THREE.Vector3(c[5], c[6], c[7]),
          new THREE.Vector3(c[2], c[3], c[4]), L, col.getHex(), 0.25 * L, 0.12 * L));
      });
    }
    three.renderer.render(three.scene, three.camera);
  }

  /* ---- the force-time plot: the force each pair of parts carries (sum over its contact
     points), divided by the reference weight; a cursor at the slider's time ---- */
  let plot;
  function setupPlot() {
    const host = $("plot");
    host.replaceChildren();
    const W = 760, H = 220, L = 52, B = 30, T = 10, Rm = 140;
    const S = R().samples, t1 = R().t_end || 1;
    const series = new Map();
    S.forEach((smp, k) => {
      const sum = new Map();
      smp.c.forEach((c) => {
        const key = c[0] < c[1] ? `${c[0]},${c[1]}` : `${c[1]},${c[0]}`;
        sum.set(key, (sum.get(key) || 0) + c[8]);
      });
      sum.forEach((f, key) => {
        if (!series.has(key)) series.set(key, []);
        series.get(key).push([smp.t, f / D.ref_weight, k]);
      });
    });
    let fmax = 0;
    series.forEach((pts) => pts.forEach((p) => (fmax = Math.max(fmax, p[1]))));
    fmax = fmax > 0 ? fmax * 1.08 : 1;
    const svgp = el("svg", { viewBox: `0 0 ${W} ${H}`, id: "plot-svg" }, host);
    const X = (t) => L + ((W - L - Rm) * t) / t1, Y = (f) => H - B - ((H - B - T) * f) / fmax;
    el("rect", { x: L, y: T, width: W - L - Rm, height: H - B - T, fill: "#fafafa", stroke: "#999" }, svgp);
    /* carried intervals shaded, as in the PNG plots */
    R().steps.forEach((st) => (st.carry || []).forEach((iv) =>
      el("rect", { x: X(iv[0]), y: T, width: Math.max(1, X(iv[1]) - X(iv[0])), height: H - B - T, fill: "#e9e3f5" }, svgp)));
    for (let k = 0; k <= 4; k++) {
      const f = (fmax * k) / 4, tt = (t1 * k) / 4;
      el("text", { x: L - 6, y: Y(f) + 4, "text-anchor": "end", "font-size": 11 }, svgp).textContent = Number(f.toPrecision(3));
      el("text", { x: X(tt), y: H - B + 16, "text-anchor": "middle", "font-size": 11 }, svgp).textContent = Number(tt.toPrecision(3));
    }
    el("text", { x: 12, y: (H - B) / 2, "font-size": 11, transform: `rotate(-90 12 ${(H - B) / 2})`, "text-anchor": "middle" }, svgp)
      .textContent = "force / W";
    el("text", { x: (W - Rm + L) / 2, y: H - 2, "font-size": 11, "text-anchor": "middle" }, svgp).textContent = "time";
    let n = 0;
    series.forEach((pts, key) => {
      /* a line per run of consecutive samples (a pair can lose and regain contact) */
      const col = `hsl(${(n * 137) % 360},65%,42%)`;
      let seg = [];
      const flush = () => {
        if (seg.length > 1) el("polyline", { points: seg.map((q) => q.join(",")).join(" "), fill: "none", stroke: col, "stroke-width": 1.6 }, svgp);
        else if (seg.length === 1) { /* a lone sample (an onset at the start): a dot and a tick, to be seen */
          el("circle", { cx: seg[0][0], cy: seg[0][1], r: 3, fill: col }, svgp);
          el("line", { x1: seg[0][0], x2: seg[0][0] + 14, y1: seg[0][1], y2: seg[0][1], stroke: col, "stroke-width": 2 }, svgp);
        }
        seg = [];
      };
      pts.forEach((p, j) => { if (j > 0 && p[2] !== pts[j - 1][2] + 1) flush(); seg.push([X(p[0]), Y(p[1])]); });
      flush();
      if (n < 12) {
        const [a, b] = key.split(",").map(Number);
        el("line", { x1: W - Rm + 8, x2: W - Rm + 24, y1: T + 8 + 14 * n, y2: T + 8 + 14 * n, stroke: col, "stroke-width": 2 }, svgp);
        el("text", { x: W - Rm + 28, y: T + 12 + 14 * n, "font-size": 11 }, svgp).textContent =
          `${bodyName(a)} / ${bodyName(b)}`;
      }
      n++;
    });
    R().steps.forEach((st) => {
      if (!st.onset) return;
      el("line", { x1: X(st.onset.time), x2: X(st.onset.time), y1: T, y2: H - B, stroke: "#c0392b", "stroke-dasharray": "4 3" }, svgp);
    });
    const cursor = el("line", { x1: L, x2: L, y1: T, y2: H - B, stroke: "#000", "stroke-width": 1.5, id: "plot-cursor" }, svgp);
    svgp.addEventListener("click", (ev) => {
      const r = svgp.getBoundingClientRect(), x = ((ev.clientX - r.left) * W) / r.width;
      setTime(Math.max(0, Math.min(t1, ((x - L) * t1) / (W - L - Rm))), true);
    });
    plot = { cursor, X };
  }

  /* ---- controls ---- */
  const slider = $("slider");
  let playing = null;
  function setTime(t, fromUser) {
    time = t;
    if (fromUser) slider.value = String(t);
    if (dim === 2) draw2d(t); else draw3d(t);
    if (plot) { const x = plot.X(t); plot.cursor.setAttribute("x1", x); plot.cursor.setAttribute("x2", x); }
    const k = stepAt(t), st = R().steps[k], onset = st ? onsetNow(t) : null;
    const names = (onset ? onset.moving : []).map(bodyName);
    $("time").textContent = fmt(t, 3);
    $("status").textContent = !st ? (D.runs.length ? "no step to play" : D.subtitle || "nothing to play") :
      `step ${k + 1} (${st.move.map(bodyName).join("+")}: ${st.status})` +
      (onset ? ` \u2014 ${onset.after ? "after removal" : "onset"} at t = ${fmt(onset.time, 3)}: ${names.join(", ")} ${names.length === 1 ? "moves" : "move"}` : "");
    /* simulate --margin: the margins of the current step's margin sample at or before t (else
       its first one): margins are found at some samples only */
    let mg = null;
    R().samples.forEach((smp) => {
      if (smp.step === k && smp.m && (mg === null || smp.t <= t + 1e-12)) mg = smp.m;
    });
    const mtext = !mg ? "" : [mg[1] !== null ? `tilt ${fmt(mg[1], 3)}\u00b0` : "",
      mg[2] !== null ? (mg[2] >= 1000 ? "lateral 1000 g or more" : `lateral ${fmt(mg[2], 3)} g`) : "",
      mg[0] !== null ? `critical friction ${fmt(mg[0], 3)}` : ""].filter((x) => x).join(", ");
    if (mtext) $("status").textContent += ` \u2014 margins here: ${mtext}`;
    $("status").dataset.margin = mtext;
    $("status").dataset.moving = names.join(",");
    $("status").dataset.onset = onset ? String(onset.time) : "";
    $("status").dataset.stepOnset = onset && st ? String(onset.time - st.t0) : "";
    document.querySelectorAll("#runs tr[data-run]").forEach((tr) => tr.classList.toggle("current", Number(tr.dataset.run) === run));
  }
  function setRun(k) {
    run = k;
    const r = R();
    slider.min = "0";
    slider.max = String(r.t_end || 0);
    slider.step = "any";
    $("verdict").textContent = `${r.label}: ${r.verdict}`;
    $("verdict").className = r.stable ? "good" : "bad";
    if (dim === 2) frame2d();
    setupPlot();
    setTime(0, true);
  }
  slider.addEventListener("input", () => setTime(Number(slider.value), false));
  $("play").addEventListener("click", () => {
    if (playing) { clearInterval(playing); playing = null; $("play").textContent = "\u25b6 play"; return; }
    const t1 = R().t_end || 0;
    if (time >= t1) setTime(0, true);
    $("play").textContent = "\u275a\u275a pause";
    playing = setInterval(() => {
      const t = Math.min(t1, time + t1 / 240);
      setTime(t, true);
      if (t >= t1) { clearInterval(playing); playing = null; $("play").textContent = "\u25b6 play"; }
    }, 40);
  });
  $("to-onset").addEventListener("click", () => {
    const st = R().steps.find((s) => s.onset);
    if (st) setTime(st.onset.time, true);
  });

  /* the runs (a simulation and its assembly run, or a plan's rows): click a row to play it */
  function setupRuns() {
    const tb = $("runs");
    const details = D.runs.some((r) => r.detail); /* a plan's rows: how the planner's table ended each */
    if (!details) $("detail-head").remove();
    D.runs.forEach((r, k) => {
      const tr = document.createElement("tr");
      tr.dataset.run = String(k);
      const cells = details ? [r.label, r.verdict, r.detail || ""] : [r.label, r.verdict];
      cells.forEach((txt) => { const td = document.createElement("td"); td.textContent = txt; tr.appendChild(td); });
      tr.addEventListener("click", () => setRun(k));
      tb.appendChild(tr);
    });
  }

  $("title").textContent = D.name || "cairn";
  $("subtitle").textContent = D.subtitle || "";
  if (dim === 2) setup2d(); else setup3d();
  setupRuns();
  setRun(0);
  /* test hooks: #run=K&t=V1,V2,... (each onset, end or a number): the slider moved to each in
     turn, as a user's drag does (an input event), and what the page then shows recorded, one
     line per time in <pre id="checks">: the value, the time, the moving parts, the onset */
  const h = new URLSearchParams(location.hash.slice(1));
  if (h.has("run")) setRun(Math.max(0, Math.min(D.runs.length - 1, Number(h.get("run")) || 0)));
  if (h.has("t")) {
    const out = document.createElement("pre");
    out.id = "checks";
    out.hidden = true;
    document.body.appendChild(out);
    h.get("t").split(",").forEach((v) => {
      const st = R().steps.find((s) => s.onset);
      const t = v === "onset" ? (st ? st.onset.time : 0) : v === "end" ? R().t_end : Number(v);
      slider.value = String(t);
      slider.dispatchEvent(new Event("input"));
      const sd = $("status").dataset;
      out.textContent += `${v}\t${time}\t${sd.moving}\t${sd.onset}\t${sd.stepOnset}\n`;
    });
  }
  document.body.dataset.ready = "1";
})();
