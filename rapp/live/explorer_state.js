// The explorers' state and geometry (part 1 of the explorer module; rapp.live.explorer_js
// concatenates core.js, this file, explorer_draw.js, explorer_drag.js and explorer.js into the one
// ES module anywidget stores in the widget state). No drawing and no events here: the model's
// values, the maps between metres, angles, grid cells and canvas pixels, and the sentences the
// status line and the screen reader say.
const R = globalThis.rappLive;
const PALETTE = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9"];
const RGB = PALETTE.map((c) => [1, 3, 5].map((i) => parseInt(c.slice(i, i + 2), 16)));
const W = 300; // logical canvas size; the page scales it to the panel's width
const INF_G = 2147483647;

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

// How far the obstacle reaches from its centroid: it stays on the canvas while its centroid
// stays this far inside the canvas's edge.
function extent(ob) {
  if (ob.type === "circle") return ob.radius;
  const c = centroid(ob);
  const v = ob.type === "polygon" ? ob.vertices
    : R.parseScenario({ arm: { link_lengths: [1, 1] }, obstacles: [ob] }).obstacles[0].v;
  return Math.max(...v.map((p) => Math.hypot(p[0] - c[0], p[1] - c[1])));
}

/** Move an obstacle's centroid to p, kept so that the whole obstacle stays within +-half. */
function moveTo(ob, p, half) {
  const room = Math.max(0, half - extent(ob));
  const q = [Math.min(room, Math.max(-room, p[0])), Math.min(room, Math.max(-room, p[1]))];
  const c = centroid(ob), dx = q[0] - c[0], dy = q[1] - c[1];
  if (ob.type === "circle") ob.center = [q[0], q[1]];
  else if (ob.type === "rectangle") ob.corner = [ob.corner[0] + dx, ob.corner[1] + dy];
  else ob.vertices = ob.vertices.map((v) => [v[0] + dx, v[1] + dy]);
}

function wrapAngle(a) {
  return a - 2 * Math.PI * Math.floor((a + Math.PI) / (2 * Math.PI));
}

/** The explorer's state, from the widget's model. */
function makeState(model) {
  const search = !!model.get("search");
  const S = {
    search,
    sweepObstacle: model.get("sweep") === undefined ? -1 : model.get("sweep"),
    scenario: clone(model.get("scenario")),
    M: model.get("cells"),
    q: model.get("q").slice(),
    start: model.get("start").slice(),
    goal: model.get("goal").slice(),
    weight: model.get("weight"),
    source: model.get("source"), // "cspace" or "paint"
    paintM: model.get("paint_cells") || 24,
    last: -1, // the obstacle moved last: its position goes into the status line
    walls: null,
    playing: false, // the search, a few expansions per frame
    perFrame: 4,
    motion: -1, // the arm moving along the path: the index of the path cell shown, -1 = not
    sweep: -1, // chapter 4's sweep: the last theta1 column painted (-1: no sweep)
    dirty: true,
    frame: 0,
    occ: null,
    layers: null,
    lastMs: 0,
    run: null, // the rappLive.Search
    buffers: R.searchBuffers(),
    snapped: "", // what the menu did to the start or goal, said once in the status line
  };
  S.walls = new Uint8Array(S.paintM * S.paintM);
  for (const [i, j] of model.get("walls")) S.walls[i * S.paintM + j] = 1;
  // The start and goal of each grid, kept when the reader switches between them.
  const m = S.paintM;
  S.ends = {
    cspace: S.source === "cspace" ? [S.start.slice(), S.goal.slice()] : null,
    paint: S.source === "paint" ? [S.start.slice(), S.goal.slice()] : [[Math.floor(m / 6), Math.floor(m / 2)], [Math.floor(5 * m / 6), Math.floor(m / 2)]],
  };
  return S;
}

/** The maps between the workspace (metres), the joint angles, the grid cells and the canvases. */
function makeGeometry(S) {
  const L = S.scenario.arm.link_lengths;
  const G = {
    L,
    reach: () => L[0] + L[1] + 0.35,
    painted: () => S.search && S.source === "paint",
    gridM: () => (G.painted() ? S.paintM : S.M),
    cellPx: () => W / G.gridM(),
  };
  G.toPx = (p) => [W / 2 + (p[0] / G.reach()) * (W / 2), W / 2 - (p[1] / G.reach()) * (W / 2)];
  G.toWorld = (x, y) => [((x - W / 2) / (W / 2)) * G.reach(), (-(y - W / 2) / (W / 2)) * G.reach()];
  // C-space canvas: theta1 to the right, theta2 up; cell i sits at the grid angle 2 pi i / M - pi.
  G.pxToCell = (x, y) => {
    const M = G.gridM(), c = G.cellPx();
    return [Math.min(M - 1, Math.max(0, Math.floor(x / c))), Math.min(M - 1, Math.max(0, Math.floor((W - y) / c)))];
  };
  G.cellToPx = (c) => [(c[0] + 0.5) * G.cellPx(), W - (c[1] + 0.5) * G.cellPx()];
  G.cellAngle = (i) => (2 * Math.PI * i) / G.gridM() - Math.PI;
  G.cellQ = (c) => [G.cellAngle(c[0]), G.cellAngle(c[1])];
  // The cell of a configuration, as rapp.JointGrid.index: the nearest grid angle, across the seam.
  G.qCell = (q) => q.map((a) => Math.round(((wrapAngle(a) + Math.PI) / (2 * Math.PI)) * G.gridM()) % G.gridM());
  G.pxToQ = (x, y) => [((x / W) * 2 - 1) * Math.PI, (((W - y) / W) * 2 - 1) * Math.PI];
  G.joints = (q) => {
    const e = [L[0] * Math.cos(q[0]), L[0] * Math.sin(q[0])];
    const a = q[0] + q[1];
    return [[0, 0], e, [e[0] + L[1] * Math.cos(a), e[1] + L[1] * Math.sin(a)]];
  };
  return G;
}

// The C-space axes' tick labels and where each sits along its axis, as a fraction of the canvas's
// width (theta1, left to right) or height (theta2, top to bottom): theta -pi .. pi spans the canvas
// as G.pxToQ maps it, so "0" is at the middle. The axis name sits between 0 and pi, unticked.
const X_TICKS = [["−π", -Math.PI], ["0", 0], ["θ₁", Math.PI / 2], ["π", Math.PI]];
const Y_TICKS = [["π", Math.PI], ["θ₂", Math.PI / 2], ["0", 0], ["−π", -Math.PI]];
/** Where the angle `a` (radians, -pi..pi) sits along an axis: 0 at -pi, 1 at pi (theta1), or,
 * with `down`, 0 at pi and 1 at -pi (theta2, drawn upwards). */
const tickAt = (a, down) => (down ? (Math.PI - a) : (a + Math.PI)) / (2 * Math.PI);

// Chapter 4's sweep: the slider and the status line both count theta1's columns from 1 to M
// (S.sweep is the 0-based column index).
const sweepSliderValue = (S) => S.sweep + 1;
const sweepFromSlider = (v) => Math.round(v) - 1;

/** The caption over the workspace: what the picture shows now. */
function workspaceCaption(S, G) {
  if (S.sweepObstacle >= 0) return "workspace: link 2 where it hits, red";
  if (!S.search) return "workspace";
  const X = S.run, n = X && X.path ? X.path.length - 1 : 0;
  if (S.motion >= 0 && n > 0) {
    const k = Math.min(S.motion, n);
    return k >= n ? "workspace: the arm at the goal, the end of its path"
      : `workspace: the arm moving along its path (step ${k} of ${n}), the goal dashed`;
  }
  return "workspace: the arm at the start, the goal dashed";
}

/** The free cell nearest to c (rings of growing Chebyshev radius, across the seams), or null. */
function nearestFree(occ, M, c) {
  if (!occ[c[0] * M + c[1]]) return c;
  for (let r = 1; r <= M / 2; r++) {
    for (let di = -r; di <= r; di++) for (let dj = -r; dj <= r; dj++) {
      if (Math.max(Math.abs(di), Math.abs(dj)) !== r) continue;
      const i = (c[0] + di + M) % M, j = (c[1] + dj + M) % M;
      if (!occ[i * M + j]) return [i, j];
    }
  }
  return null;
}

// ---- what the screen reader and the status line say
const fmt = (v, d) => {
  const s = v.toFixed(d === undefined ? 2 : d);
  return /^-0\.?0*$/.test(s) ? s.slice(1) : s.replace("-", "−");
};

function obstacleText(S, k) {
  const p = centroid(S.scenario.obstacles[k]);
  return `obstacle ${k + 1} at (${fmt(p[0])}, ${fmt(p[1])}) m`;
}

function cellText(G, name, c) {
  const q = G.cellQ(c);
  return G.painted() ? `${name} at cell (${c[0]}, ${c[1]})`
    : `${name} at θ₁ ${fmt(q[0])} rad, θ₂ ${fmt(q[1])} rad`;
}

/** The status line: sentences a student reads (and a screen reader says after each move). */
function statusText(S, G, crossings) {
  const M = G.gridM(), occ = S.occ;
  const frac = occ ? occ.reduce((a, b) => a + b, 0) / occ.length : 0;
  const pct = `${(100 * frac).toFixed(1)} %`;
  const parts = [];
  if (S.sweepObstacle >= 0) {
    const k = S.sweepObstacle, lay = S.layers && S.layers[k];
    if (S.sweep >= 0 && lay) {
      let hit = 0;
      for (let j = 0; j < M; j++) hit += lay[S.sweep * M + j];
      const a = G.cellAngle(S.sweep);
      parts.push(`θ₁ = ${fmt(a)} rad (column ${S.sweep + 1} of ${M}): link 2 hits obstacle ${k + 1} at ${hit} of the ${M} values of θ₂` +
        (hit === M ? " (every one: link 1 itself touches it)." : "."));
    } else {
      parts.push(`Press “sweep θ₁” to build obstacle ${k + 1}’s C-space region column by column.`);
    }
    return parts.join(" ");
  }
  if (G.painted()) parts.push(`${pct} of the ${M} × ${M} cells are walls.`);
  else parts.push(`${pct} of the cells collide (grid ${M} × ${M}, recomputed in ${S.lastMs.toFixed(1)} ms).`);
  if (S.last >= 0 && !G.painted()) {
    const p = centroid(S.scenario.obstacles[S.last]);
    parts.push(`Obstacle ${S.last + 1} is at (${fmt(p[0])}, ${fmt(p[1])}) m, ${fmt(Math.hypot(p[0], p[1]))} m from the base.`);
  }
  if (!S.search) {
    const ci = G.qCell(S.q);
    parts.push(`The arm at θ = (${fmt(S.q[0])}, ${fmt(S.q[1])}) rad, cell (${ci[0]}, ${ci[1]}), ` +
      (occ[ci[0] * M + ci[1]] ? "collides." : "is free."));
    return parts.join(" ");
  }
  if (S.snapped) parts.push(S.snapped);
  const X = S.run;
  if (!X) return parts.join(" ");
  const w = S.weight === 1 ? "" : ` (heuristic weight ${S.weight})`;
  if (X.status === "found") {
    const n = crossings[0] + crossings[1];
    parts.push(`A*${w} found a path of ${X.path.length - 1} steps after expanding ${X.expansions} cells ` +
      `(${X.openCount()} left on the open list)` +
      (n ? `; it crosses the seam ${n === 1 ? "once" : n === 2 ? "twice" : n + " times"}.` : "; it does not cross the seam."));
    // Said once the arm arrives (not at every step: a screen reader would say each one).
    if (S.motion >= X.path.length - 1) parts.push("The arm has moved along it to the goal.");
  } else if (X.status === "blocked") parts.push(`The ${X.blockedEnd} cell is blocked, so A*${w} cannot start.`);
  else if (X.status === "unreachable") parts.push(`No path: A*${w} expanded all ${X.expansions} cells reachable from the start.`);
  else parts.push(`A* is searching: ${X.expansions} cells expanded, ${X.openCount()} on the open list.`);
  return parts.join(" ");
}
