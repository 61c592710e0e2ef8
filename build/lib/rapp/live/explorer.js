// The explorers of chapters 4 and 5 (an anywidget ES module; core.js is prepended to it).
// Workspace and C-space side by side; the reader drags obstacles, the arm's joints or its point in
// C-space; the grid is recomputed on the next animation frame (never per mouse event). With
// `search` on, A* (rappLive.Search) runs on that grid or on a small grid the reader paints.
const R = globalThis.rappLive;
const PALETTE = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9"];
const RGB = PALETTE.map((c) => [1, 3, 5].map((i) => parseInt(c.slice(i, i + 2), 16)));
const CSS = `
.rapp-live{font:13px/1.35 system-ui,sans-serif;max-width:100%;overflow-x:auto;color:#222}
.rapp-live .rl-row{display:flex;flex-wrap:wrap;gap:10px;align-items:flex-start}
.rapp-live .rl-panel{position:relative;touch-action:none;user-select:none}
.rapp-live canvas{display:block;border:1px solid #bbb;background:#fff;max-width:100%}
.rapp-live .rl-h{position:absolute;width:16px;height:16px;margin:-8px 0 0 -8px;border-radius:50%;
  border:2px solid #222;background:rgba(255,255,255,.6);cursor:grab;box-sizing:border-box}
.rapp-live .rl-h:focus{outline:2px solid #E69F00}
.rapp-live .rl-ctl{display:flex;flex-wrap:wrap;gap:8px 14px;align-items:center;margin:6px 0}
.rapp-live .rl-ctl button{font:inherit;padding:1px 8px}
.rapp-live .rl-status{font-family:ui-monospace,monospace;font-size:12px;margin:4px 0}
.rapp-live .rl-note{font-size:12px;color:#555;margin:4px 0;max-width:640px}
.rapp-live .rl-cap{font-size:12px;color:#333;margin:2px 0;max-width:300px}`;

function el(tag, attrs, parent) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === "text") e.textContent = v;
    else e.setAttribute(k, v);
  }
  if (parent) parent.appendChild(e);
  return e;
}

function clone(x) {
  return JSON.parse(JSON.stringify(x));
}

function centroid(ob) {
  if (ob.type === "circle") return ob.center.slice();
  if (ob.type === "rectangle") {
    const a = ob.angle || 0, c = Math.cos(a), s = Math.sin(a), w = ob.width / 2, h = ob.height / 2;
    return [ob.corner[0] + w * c - h * s, ob.corner[1] + w * s + h * c];
  }
  const v = ob.vertices;
  return [v.reduce((t, p) => t + p[0], 0) / v.length, v.reduce((t, p) => t + p[1], 0) / v.length];
}

function moveTo(ob, p) {
  const c = centroid(ob), dx = p[0] - c[0], dy = p[1] - c[1];
  if (ob.type === "circle") ob.center = [p[0], p[1]];
  else if (ob.type === "rectangle") ob.corner = [ob.corner[0] + dx, ob.corner[1] + dy];
  else ob.vertices = ob.vertices.map((v) => [v[0] + dx, v[1] + dy]);
}

function wrapAngle(a) {
  return a - 2 * Math.PI * Math.floor((a + Math.PI) / (2 * Math.PI));
}

function render({ model, el: host }) {
  const search = !!model.get("search");
  const S = {
    scenario: clone(model.get("scenario")),
    M: model.get("cells"),
    q: model.get("q").slice(),
    start: model.get("start").slice(),
    goal: model.get("goal").slice(),
    weight: model.get("weight"),
    source: model.get("source"), // "cspace" or "paint"
    paintM: model.get("paint_cells") || 24,
    last: -1, // the obstacle dragged last: its position goes into the status line
    walls: null,
    playing: false,
    perFrame: 4,
    dirty: true,
    frame: 0,
  };
  S.walls = new Uint8Array(S.paintM * S.paintM);
  for (const [i, j] of model.get("walls")) S.walls[i * S.paintM + j] = 1;

  const root = el("div", { class: "rapp-live", "data-rapp-live": search ? "astar" : "cspace" }, host);
  el("style", { text: CSS }, root);
  const ctl = el("div", { class: "rl-ctl" }, root);
  const row = el("div", { class: "rl-row" }, root);
  const W = 300;
  const wsPanel = el("div", { class: "rl-panel" }, row);
  el("div", { class: "rl-cap", text: search
    ? "workspace: drag the obstacles; the arm is at the start (drag its elbow or tip to move the start)"
    : "workspace (drag the obstacles, the elbow, the tip)" }, wsPanel);
  const ws = el("canvas", { width: W, height: W, "data-rapp-drag": "workspace" }, wsPanel);
  const csPanel = el("div", { class: "rl-panel" }, row);
  const csCap = el("div", { class: "rl-cap" }, csPanel);
  const cs = el("canvas", { width: W, height: W, "data-rapp-drag": "cspace" }, csPanel);
  const DPR = Math.min(3, Math.max(1, Math.round(window.devicePixelRatio || 1)));
  for (const cv of [ws, cs]) {
    cv.width = cv.height = W * DPR;
    cv.style.width = W + "px";
  }
  const ctx2d = (cv) => {
    const x = cv.getContext("2d");
    x.setTransform(DPR, 0, 0, DPR, 0, 0);
    return x;
  };
  const status = el("div", { class: "rl-status", "aria-live": "polite" }, root);
  el("div", {
    class: "rl-note",
    text: search
      ? "Computed in this page, in JavaScript: the C-space by rapp.occupancy's closed-form interval per link and obstacle, " +
        "and A* as rapp.astar runs it: unit steps to the 4 neighbours (across the seam on a wrapping axis), " +
        "f = g + w·h with the toroidal Manhattan heuristic GD1, ties to the larger g, then the smaller cell number; " +
        "blue: closed set, yellow: open list; orange-red squares: where the path crosses the seam. tests/test_live.py checks both against rapp."
      : "Computed in this page, in JavaScript, on every move: for each link and obstacle the closed-form interval of " +
        "joint angles at which the link touches it (rapp.occupancy), painted onto the grid; tests/test_live.py checks " +
        "the grid against rapp.occupancy. The dashed orange-red border is the seam: θ = −π and θ = π are the same angle.",
  }, root);

  // ---- controls
  const L = S.scenario.arm.link_lengths;
  function slider(label, min, max, step, value, on, parent) {
    const lab = el("label", {}, parent || ctl);
    lab.append(label + " ");
    const inp = el("input", { type: "range", min, max, step, value }, lab);
    const out = el("span", { text: String(value) }, lab);
    inp.addEventListener("input", () => {
      out.textContent = inp.value;
      on(+inp.value);
      schedule();
    });
    inp.addEventListener("change", () => sync());
    return inp;
  }
  // The arm's controls; hidden while the A* explorer searches a painted grid, which has no arm.
  const armCtl = el("span", { class: "rl-ctl", style: "margin:0" }, ctl);
  slider("link 1 (m)", 0.3, 1.5, 0.05, L[0], (v) => { L[0] = v; S.dirty = true; }, armCtl);
  slider("link 2 (m)", 0.3, 1.5, 0.05, L[1], (v) => { L[1] = v; S.dirty = true; }, armCtl);
  slider("cells M", 24, 180, 2, S.M, (v) => { S.M = v; S.dirty = true; }, armCtl);
  let playBtn = null;
  if (search) {
    const sel = el("select", {}, ctl);
    [["cspace", "grid: the C-space"], ["paint", "grid: paint walls (" + S.paintM + " × " + S.paintM + ")"]].forEach(([v, t]) => {
      const o = el("option", { value: v, text: t }, sel);
      if (v === S.source) o.selected = true;
    });
    sel.addEventListener("change", () => { S.source = sel.value; resetEnds(); S.dirty = true; schedule(); });
    slider("weight w", 1, 3, 0.25, S.weight, (v) => { S.weight = v; S.dirty = true; });
    playBtn = el("button", { text: "▶ play" }, ctl);
    const stepBtn = el("button", { text: "step" }, ctl);
    const endBtn = el("button", { text: "to the end" }, ctl);
    slider("speed", 1, 40, 1, S.perFrame, (v) => { S.perFrame = v; });
    playBtn.addEventListener("click", () => {
      flush();
      if (!S.playing && S.search && S.search.status !== "running") restartSearch();
      S.playing = !S.playing;
      playBtn.textContent = S.playing ? "❚❚ pause" : "▶ play";
      tick();
    });
    stepBtn.addEventListener("click", () => {
      flush();
      if (S.search && S.search.status !== "running") restartSearch();
      S.playing = false;
      playBtn.textContent = "▶ play";
      S.search.step(1);
      draw();
    });
    endBtn.addEventListener("click", () => { flush(); S.playing = false; playBtn.textContent = "▶ play"; S.search.step(Infinity); draw(); });
  }

  // ---- geometry of the two panels
  const reach = () => L[0] + L[1] + 0.35;
  const toPx = (p) => [W / 2 + (p[0] / reach()) * (W / 2), W / 2 - (p[1] / reach()) * (W / 2)];
  const toWorld = (x, y) => [((x - W / 2) / (W / 2)) * reach(), (-(y - W / 2) / (W / 2)) * reach()];
  const gridM = () => (search && S.source === "paint" ? S.paintM : S.M);
  // C-space canvas: theta1 to the right, theta2 up, cell centres at the grid angles.
  const cellPx = () => W / gridM();
  const qToPx = (q) => [((wrapAngle(q[0]) + Math.PI) / (2 * Math.PI)) * W + cellPx() / 2,
    W - (((wrapAngle(q[1]) + Math.PI) / (2 * Math.PI)) * W + cellPx() / 2)];
  const pxToCell = (x, y) => {
    const M = gridM(), c = cellPx();
    return [Math.min(M - 1, Math.max(0, Math.floor(x / c))), Math.min(M - 1, Math.max(0, Math.floor((W - y) / c)))];
  };
  const cellToPx = (c) => [(c[0] + 0.5) * cellPx(), W - (c[1] + 0.5) * cellPx()];
  const joints = () => {
    const e = [L[0] * Math.cos(S.q[0]), L[0] * Math.sin(S.q[0])];
    const a = S.q[0] + S.q[1];
    return [[0, 0], e, [e[0] + L[1] * Math.cos(a), e[1] + L[1] * Math.sin(a)]];
  };

  // ---- handles: DOM elements a reader (or a test) drags; they set pending state, redrawn per frame
  const handles = [];
  function handle(panel, name, title, onMove) {
    const h = el("div", { class: "rl-h", "data-rapp-drag": name, title, tabindex: "0", role: "slider", "aria-label": title }, panel);
    h.addEventListener("pointerdown", (ev) => {
      ev.preventDefault();
      h.setPointerCapture(ev.pointerId);
      const canvas = panel.querySelector("canvas");
      const move = (e) => {
        const r = canvas.getBoundingClientRect();
        const sx = W / r.width;
        onMove((e.clientX - r.left) * sx, (e.clientY - r.top) * sx);
        S.dirty = true;
        schedule();
      };
      const up = () => { h.removeEventListener("pointermove", move); h.removeEventListener("pointerup", up); sync(); };
      h.addEventListener("pointermove", move);
      h.addEventListener("pointerup", up);
    });
    h.addEventListener("keydown", (e) => {
      const d = { ArrowLeft: [-4, 0], ArrowRight: [4, 0], ArrowUp: [0, -4], ArrowDown: [0, 4] }[e.key];
      if (!d) return;
      e.preventDefault();
      const x = parseFloat(h.style.left) || 0, y = parseFloat(h.style.top) || 0;
      const r = panel.querySelector("canvas"), off = [r.offsetLeft, r.offsetTop];
      onMove(x - off[0] + d[0], y - off[1] + d[1]);
      S.dirty = true;
      schedule();
      sync();
    });
    handles.push({ h, panel });
    return h;
  }
  function place(h, canvas, p) {
    const s = canvas.getBoundingClientRect().width / W || 1;
    h.style.left = canvas.offsetLeft + p[0] * s + "px";
    h.style.top = canvas.offsetTop + p[1] * s + "px";
  }
  const obHandles = S.scenario.obstacles.map((ob, k) =>
    handle(wsPanel, "obstacle-" + k, "obstacle " + (k + 1) + ": drag to move it", (x, y) => { S.last = k; moveTo(ob, toWorld(x, y)); }));
  // The cell of a configuration, as rapp.JointGrid.index: the nearest grid angle, across the seam.
  const qCell = (q) => q.map((a) => Math.round(((wrapAngle(a) + Math.PI) / (2 * Math.PI)) * gridM()) % gridM());
  const elbowH = handle(wsPanel, "elbow", "elbow: drag to turn joint 1", (x, y) => {
    const p = toWorld(x, y);
    S.q[0] = Math.atan2(p[1], p[0]);
    if (search) S.start = qCell(S.q);
  });
  const tipH = handle(wsPanel, "tip", "tip: drag to turn joint 2", (x, y) => {
    const p = toWorld(x, y), e = joints()[1];
    S.q[1] = wrapAngle(Math.atan2(p[1] - e[1], p[0] - e[0]) - S.q[0]);
    if (search) S.start = qCell(S.q);
  });
  const qH = handle(csPanel, "configuration", "the configuration: drag it through C-space", (x, y) => {
    S.q = [((x / W) * 2 - 1) * Math.PI, (((W - y) / W) * 2 - 1) * Math.PI];
  });
  let startH = null, goalH = null;
  if (search) {
    startH = handle(csPanel, "start", "start: drag it", (x, y) => { S.start = pxToCell(x, y); });
    goalH = handle(csPanel, "goal", "goal: drag it", (x, y) => { S.goal = pxToCell(x, y); });
    startH.style.background = "#009E73";
    goalH.style.background = "#D55E00";
    qH.style.display = "none";
    // Paint walls on the small grid: press and drag; the first cell decides paint or erase.
    let painting = -1;
    cs.addEventListener("pointerdown", (e) => {
      if (S.source !== "paint") return;
      const r = cs.getBoundingClientRect(), c = pxToCell((e.clientX - r.left) * W / r.width, (e.clientY - r.top) * W / r.width);
      painting = S.walls[c[0] * S.paintM + c[1]] ? 0 : 1;
      cs.setPointerCapture(e.pointerId);
      paintAt(e);
    });
    const paintAt = (e) => {
      const r = cs.getBoundingClientRect(), c = pxToCell((e.clientX - r.left) * W / r.width, (e.clientY - r.top) * W / r.width);
      S.walls[c[0] * S.paintM + c[1]] = painting;
      S.dirty = true;
      schedule();
    };
    cs.addEventListener("pointermove", (e) => { if (painting >= 0) paintAt(e); });
    cs.addEventListener("pointerup", () => { painting = -1; });
  } else {
    cs.addEventListener("pointerdown", (e) => {
      const r = cs.getBoundingClientRect();
      const x = (e.clientX - r.left) * W / r.width, y = (e.clientY - r.top) * W / r.width;
      S.q = [((x / W) * 2 - 1) * Math.PI, (((W - y) / W) * 2 - 1) * Math.PI];
      S.dirty = true;
      schedule();
      sync();
    });
  }
  function resetEnds() {
    const M = gridM();
    S.start = [Math.round(M * 0.15), Math.round(M * 0.5)];
    S.goal = [Math.round(M * 0.85), Math.round(M * 0.5)];
  }

  // ---- computation (on an animation frame only)
  let occ = null, layers = null, lastMs = 0;
  function recompute() {
    const t0 = performance.now();
    const M = gridM();
    if (search && S.source === "paint") {
      occ = S.walls.slice();
      layers = null;
    } else {
      layers = R.occupancyOf(R.parseScenario(S.scenario), M, true);
      occ = new Uint8Array(M * M);
      for (const lay of layers) for (let i = 0; i < occ.length; i++) occ[i] |= lay[i];
    }
    if (search) {
      S.start = S.start.map((v) => Math.min(M - 1, Math.max(0, v)));
      S.goal = S.goal.map((v) => Math.min(M - 1, Math.max(0, v)));
      restartSearch();
      if (!S.playing) S.search.step(Infinity);
    }
    lastMs = performance.now() - t0;
    S.frame += 1;
    root.setAttribute("data-rapp-frame", String(S.frame));
    root.setAttribute("data-rapp-ms", lastMs.toFixed(2));
  }
  function restartSearch() {
    const M = gridM();
    S.search = new R.Search(occ, [M, M], S.start, S.goal, { weight: S.weight, wraps: [true, true] });
  }

  // ---- drawing
  const off = document.createElement("canvas");
  function draw() {
    const M = gridM();
    csCap.textContent = search && S.source === "paint"
      ? "a " + M + " × " + M + " grid, both axes wrap (click and drag to paint or erase walls)"
      : "C-space, θ1 → and θ2 ↑ from −π to π (" + M + " × " + M + " cells)";
    wsPanel.style.display = armCtl.style.display = search && S.source === "paint" ? "none" : "";
    // C-space image: one pixel per cell, scaled up without smoothing.
    off.width = M; off.height = M;
    const ctx0 = off.getContext("2d"), img = ctx0.createImageData(M, M), d = img.data;
    const Sx = S.search;
    for (let i = 0; i < M; i++) for (let j = 0; j < M; j++) {
      const k = i * M + j, p = ((M - 1 - j) * M + i) * 4;
      let c = [255, 255, 255];
      if (occ[k]) {
        c = [150, 150, 150];
        if (layers) for (let o = 0; o < layers.length; o++) if (layers[o][k]) { c = RGB[o % RGB.length].map((v) => 0.55 * v + 40); break; }
      } else if (Sx && Sx.closed[k]) c = [170, 205, 240];
      else if (Sx && Sx.g[k] > 0 && Sx.g[k] < 2147483647) c = [240, 228, 66];
      d[p] = c[0]; d[p + 1] = c[1]; d[p + 2] = c[2]; d[p + 3] = 255;
    }
    ctx0.putImageData(img, 0, 0);
    const c = ctx2d(cs);
    c.imageSmoothingEnabled = false;
    c.clearRect(0, 0, W, W);
    c.drawImage(off, 0, 0, W, W);
    // The seam: the square's edges are one circle per axis.
    c.save();
    c.strokeStyle = "#D55E00"; c.lineWidth = 3; c.setLineDash([6, 4]);
    c.strokeRect(1.5, 1.5, W - 3, W - 3);
    c.restore();
    let crossings = [0, 0];
    if (Sx && Sx.path) {
      const cells = R.toCells(Sx.path, M);
      c.strokeStyle = "#000"; c.lineWidth = 2.5; c.beginPath();
      for (let k = 0; k < cells.length; k++) {
        const p = cellToPx(cells[k]);
        const jump = k > 0 && (Math.abs(cells[k][0] - cells[k - 1][0]) > 1 || Math.abs(cells[k][1] - cells[k - 1][1]) > 1);
        if (jump) {
          crossings[Math.abs(cells[k][0] - cells[k - 1][0]) > 1 ? 0 : 1] += 1;
          // Leave through one edge and come back through the opposite one.
          const q = cellToPx(cells[k - 1]), dx = cells[k][0] - cells[k - 1][0], dy = cells[k][1] - cells[k - 1][1];
          const ex = dx > 1 ? -cellPx() : dx < -1 ? cellPx() : 0, ey = dy > 1 ? cellPx() : dy < -1 ? -cellPx() : 0;
          c.lineTo(q[0] + ex, q[1] + ey);
          c.moveTo(p[0] - ex, p[1] - ey);
          c.fillStyle = "#D55E00";
          const edge = (v) => Math.min(W - 5, Math.max(5, v));
          c.fillRect(edge(q[0] + ex / 2) - 5, edge(q[1] + ey / 2) - 5, 10, 10);
          c.fillRect(edge(p[0] - ex / 2) - 5, edge(p[1] - ey / 2) - 5, 10, 10);
        }
        if (k === 0) c.moveTo(p[0], p[1]); else c.lineTo(p[0], p[1]);
      }
      c.stroke();
    }
    if (Sx && Sx.current >= 0 && Sx.status === "running") {
      const p = cellToPx([(Sx.current / M) | 0, Sx.current % M]);
      c.strokeStyle = "#000"; c.lineWidth = 2; c.strokeRect(p[0] - cellPx() / 2, p[1] - cellPx() / 2, cellPx(), cellPx());
    }
    // Workspace.
    const w = ctx2d(ws);
    w.clearRect(0, 0, W, W);
    w.strokeStyle = "#ddd"; w.setLineDash([3, 3]); w.beginPath();
    const o = toPx([0, 0]), rpx = ((L[0] + L[1]) / reach()) * (W / 2);
    w.arc(o[0], o[1], rpx, 0, 2 * Math.PI); w.stroke(); w.setLineDash([]);
    S.scenario.obstacles.forEach((ob, k) => {
      w.fillStyle = PALETTE[k % PALETTE.length] + "99";
      w.strokeStyle = PALETTE[k % PALETTE.length];
      w.beginPath();
      if (ob.type === "circle") {
        const p = toPx(ob.center);
        w.arc(p[0], p[1], (ob.radius / reach()) * (W / 2), 0, 2 * Math.PI);
      } else {
        const v = R.parseScenario({ arm: { link_lengths: [1, 1] }, obstacles: [ob] }).obstacles[0].v;
        v.forEach((pt, i) => { const p = toPx(pt); if (i) w.lineTo(p[0], p[1]); else w.moveTo(p[0], p[1]); });
        w.closePath();
      }
      w.fill(); w.stroke();
      place(obHandles[k], ws, toPx(centroid(ob)));
    });
    // In the A* explorer the arm shows the start configuration (the cell's grid angles).
    if (search && S.source === "cspace") S.q = S.start.map((i) => (2 * Math.PI * i) / M - Math.PI);
    const J = joints().map(toPx);
    const M0 = gridM();
    const ci = qCell(S.q);
    // Red where the arm collides: at the configuration, or (A* explorer) at the start cell.
    const hit = occ && (search ? S.search && S.search.blockedEnd === "start" : occ[ci[0] * M0 + ci[1]]);
    w.strokeStyle = hit ? "#D55E00" : "#222"; w.lineWidth = 5; w.lineCap = "round";
    w.beginPath(); w.moveTo(J[0][0], J[0][1]); w.lineTo(J[1][0], J[1][1]); w.lineTo(J[2][0], J[2][1]); w.stroke();
    w.fillStyle = "#222"; w.beginPath(); w.arc(J[0][0], J[0][1], 5, 0, 2 * Math.PI); w.fill();
    place(elbowH, ws, J[1]);
    place(tipH, ws, J[2]);
    place(qH, cs, cellToPx(ci));
    if (search) { place(startH, cs, cellToPx(S.start)); place(goalH, cs, cellToPx(S.goal)); }
    else {
      // The configuration in C-space: a cross on the cell nearest to q.
      const p = cellToPx(ci);
      c.strokeStyle = "#000"; c.lineWidth = 2; c.beginPath();
      c.moveTo(p[0] - 9, p[1]); c.lineTo(p[0] + 9, p[1]); c.moveTo(p[0], p[1] - 9); c.lineTo(p[0], p[1] + 9); c.stroke();
    }
    // Status line.
    let moved = "";
    if (S.last >= 0 && !(search && S.source === "paint")) {
      const p = centroid(S.scenario.obstacles[S.last]);
      moved = ` · obstacle ${S.last + 1} at (${p[0].toFixed(2)}, ${p[1].toFixed(2)}) m, ${Math.hypot(p[0], p[1]).toFixed(2)} m from the base`;
    }
    const frac = occ ? occ.reduce((a, b) => a + b, 0) / occ.length : 0;
    const what = search && S.source === "paint" ? "are walls" : "collide";
    let txt = `grid ${M} × ${M}: ${(100 * frac).toFixed(1)} % of the cells ${what} · recomputed in ${lastMs.toFixed(1)} ms`;
    if (!search) {
      txt += ` · q = (${S.q[0].toFixed(2)}, ${S.q[1].toFixed(2)}) rad, cell (${ci[0]}, ${ci[1]}): ` + (hit ? "COLLIDES" : "free");
    } else if (Sx) {
      const open = Sx.openCells().length;
      txt += ` · w = ${S.weight} · expansions ${Sx.expansions}, open ${open}`;
      if (Sx.status === "found") txt += ` · path ${Sx.path.length - 1} steps` +
        (crossings[0] + crossings[1] ? `, crosses the seam ${crossings[0] + crossings[1]}× (θ1: ${crossings[0]}, θ2: ${crossings[1]})` : ", no seam crossing");
      else if (Sx.status === "blocked") txt += ` · the ${Sx.blockedEnd} cell is blocked: no search`;
      else if (Sx.status === "unreachable") txt += " · NO PATH: every cell reachable from the start is closed";
      else txt += " · searching…";
    }
    status.textContent = txt + moved;
  }

  // ---- the frame loop: at most one recompute and one drawing per animation frame
  function flush() {
    if (S.dirty) { S.dirty = false; recompute(); }
  }
  let pending = false;
  function schedule() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      flush();
      draw();
    });
  }
  function tick() {
    if (!S.playing) return;
    if (S.search.status === "running") S.search.step(S.perFrame);
    draw();
    if (S.search.status !== "running") {
      S.playing = false;
      if (playBtn) playBtn.textContent = "▶ play";
      return;
    }
    requestAnimationFrame(tick);
  }
  // In JupyterLab the Python side sees where the reader left things; the static book has no
  // kernel, so saving may fail there, harmlessly.
  function sync() {
    try {
      model.set("q", S.q.slice());
      model.set("scenario", clone(S.scenario));
      model.set("cells", S.M);
      if (search) { model.set("start", S.start.slice()); model.set("goal", S.goal.slice()); model.set("weight", S.weight); }
      const r = model.save_changes();
      if (r && r.catch) r.catch(() => {});
    } catch (e) { /* no kernel */ }
  }
  recompute();
  draw();
  // Sizes are known only once the element is in the page: place the handles again then.
  requestAnimationFrame(() => draw());
  if (typeof ResizeObserver !== "undefined") new ResizeObserver(() => draw()).observe(root);
}

export default { render };
