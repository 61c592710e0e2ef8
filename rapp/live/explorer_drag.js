// Dragging (part 3 of the explorer module): handles a finger, a mouse or the keyboard moves.
// A handle is a 36 x 36 px element (a finger's hit area; the ring drawn in it is 18 px) with
// role="slider": Tab reaches it, the arrow keys move it, and it announces its value
// (aria-valuenow, aria-valuetext). A move only changes the state and asks for a frame; the grid
// is recomputed on the next animation frame, never per pointer event.

const HANDLE_CSS = `
.rapp-live .rl-h{position:absolute;width:36px;height:36px;margin:-18px 0 0 -18px;border-radius:50%;
  cursor:grab;box-sizing:border-box;touch-action:none;z-index:2}
.rapp-live .rl-h::after{content:"";position:absolute;left:9px;top:9px;width:18px;height:18px;border-radius:50%;
  border:2px solid #222;background:var(--rl-fill,rgba(255,255,255,.6));box-sizing:border-box}
.rapp-live .rl-h:focus{outline:none}
.rapp-live .rl-h:focus-visible::after,.rapp-live .rl-h:focus::after{box-shadow:0 0 0 3px #E69F00}`;

/** Event coordinates in the canvas's logical pixels (the canvas may be drawn smaller). */
function logical(canvas, e) {
  const r = canvas.getBoundingClientRect(), s = W / (r.width || W);
  return [(e.clientX - r.left) * s, (e.clientY - r.top) * s];
}

/**
 * A draggable handle.
 *
 * spec: {panel, canvas, name, label, drag(x, y) in logical canvas pixels, key(dx, dy) with
 * dx, dy in {-1, 0, 1} (right and up positive), value() -> {now, min, max, text}}.
 * changed(final) is called after every move (final: the drag or key press is over).
 */
function makeHandle(spec, changed) {
  const h = el("div", { class: "rl-h", "data-rapp-drag": spec.name, title: spec.label, tabindex: "0", role: "slider",
    "aria-label": spec.label, "aria-orientation": "horizontal" }, spec.panel);
  h.addEventListener("pointerdown", (ev) => {
    ev.preventDefault();
    h.focus({ preventScroll: true });
    try { h.setPointerCapture(ev.pointerId); } catch (e) { /* synthetic events */ }
    const move = (e) => { spec.drag(...logical(spec.canvas, e)); changed(false); };
    const up = () => {
      h.removeEventListener("pointermove", move);
      h.removeEventListener("pointerup", up);
      h.removeEventListener("pointercancel", up);
      changed(true);
    };
    h.addEventListener("pointermove", move);
    h.addEventListener("pointerup", up);
    h.addEventListener("pointercancel", up);
  });
  h.addEventListener("keydown", (e) => {
    const d = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, 1], ArrowDown: [0, -1] }[e.key];
    if (!d) return;
    e.preventDefault();
    spec.key(d[0], d[1]);
    changed(true);
  });
  return {
    h,
    spec,
    /** Put the handle at p (logical canvas pixels) and refresh what it announces. */
    place(p) {
      const s = spec.canvas.getBoundingClientRect().width / W || 1;
      h.style.left = spec.canvas.offsetLeft + p[0] * s + "px";
      h.style.top = spec.canvas.offsetTop + p[1] * s + "px";
      const v = spec.value();
      h.setAttribute("aria-valuenow", v.now.toFixed(2));
      h.setAttribute("aria-valuemin", v.min.toFixed(2));
      h.setAttribute("aria-valuemax", v.max.toFixed(2));
      h.setAttribute("aria-valuetext", v.text);
    },
  };
}

/** Every handle of an explorer: obstacles, elbow, tip, and the C-space point or start and goal. */
function makeHandles(S, G, P, changed) {
  const STEP_M = 0.05, STEP_RAD = 0.05;
  const half = () => G.reach();
  const list = [];
  const add = (spec) => { const x = makeHandle(spec, changed); list.push(x); return x; };
  S.scenario.obstacles.forEach((ob, k) => {
    const val = () => { const p = centroid(ob); return { now: p[0], min: -half(), max: half(), text: obstacleText(S, k) }; };
    const x = add({ panel: P.wsPanel, canvas: P.ws, name: "obstacle-" + k, label: "obstacle " + (k + 1),
      drag: (px, py) => { S.last = k; moveTo(ob, G.toWorld(px, py), half()); S.dirty = true; },
      key: (dx, dy) => { S.last = k; const c = centroid(ob); moveTo(ob, [c[0] + dx * STEP_M, c[1] + dy * STEP_M], half()); S.dirty = true; },
      value: val });
    x.where = () => G.toPx(centroid(ob));
    x.shown = () => !G.painted();
  });
  const setQ = (q) => {
    S.q = [wrapAngle(q[0]), wrapAngle(q[1])];
    if (S.search) { S.start = G.qCell(S.q); S.motion = -1; S.dirty = true; }
  };
  const angle = (i) => ({ now: S.search ? G.cellQ(S.start)[i] : S.q[i], min: -Math.PI, max: Math.PI,
    text: `θ${i ? "₂" : "₁"} ${fmt(S.search ? G.cellQ(S.start)[i] : S.q[i])} rad` });
  const current = () => (S.search ? G.cellQ(S.start) : S.q);
  const elbow = add({ panel: P.wsPanel, canvas: P.ws, name: "elbow", label: "elbow (joint 1)",
    drag: (px, py) => { const p = G.toWorld(px, py); setQ([Math.atan2(p[1], p[0]), current()[1]]); },
    key: (dx, dy) => { const q = current(); setQ([q[0] + (dx + dy) * (S.search ? 2 * Math.PI / G.gridM() : STEP_RAD), q[1]]); },
    value: () => angle(0) });
  elbow.where = () => G.toPx(G.joints(current())[1]);
  elbow.shown = () => !G.painted() && S.sweepObstacle < 0 && S.motion < 0;
  const tip = add({ panel: P.wsPanel, canvas: P.ws, name: "tip", label: "tip (joint 2)",
    drag: (px, py) => { const p = G.toWorld(px, py), q = current(), e = G.joints(q)[1]; setQ([q[0], Math.atan2(p[1] - e[1], p[0] - e[0]) - q[0]]); },
    key: (dx, dy) => { const q = current(); setQ([q[0], q[1] + (dx + dy) * (S.search ? 2 * Math.PI / G.gridM() : STEP_RAD)]); },
    value: () => angle(1) });
  tip.where = () => G.toPx(G.joints(current())[2]);
  tip.shown = elbow.shown;
  if (!S.search) {
    const cq = add({ panel: P.csPanel, canvas: P.cs, name: "configuration", label: "configuration in C-space",
      drag: (px, py) => { S.q = G.pxToQ(px, py); },
      key: (dx, dy) => { S.q = [wrapAngle(S.q[0] + dx * STEP_RAD), wrapAngle(S.q[1] + dy * STEP_RAD)]; },
      value: () => ({ now: S.q[0], min: -Math.PI, max: Math.PI, text: `θ₁ ${fmt(S.q[0])} rad, θ₂ ${fmt(S.q[1])} rad` }) });
    cq.where = () => G.cellToPx(G.qCell(S.q));
    cq.shown = () => S.sweepObstacle < 0;
    return list;
  }
  const end = (k, name) => {
    const x = add({ panel: P.csPanel, canvas: P.cs, name, label: name,
      drag: (px, py) => { S[name] = G.pxToCell(px, py); S.motion = -1; S.dirty = true; },
      key: (dx, dy) => { const M = G.gridM(); S[name] = [(S[name][0] + dx + M) % M, (S[name][1] + dy + M) % M]; S.motion = -1; S.dirty = true; },
      value: () => ({ now: S[name][0], min: 0, max: G.gridM() - 1, text: cellText(G, name, S[name]) }) });
    x.h.style.setProperty("--rl-fill", k ? "#D55E00" : "#009E73");
    x.where = () => G.cellToPx(S[name]);
    x.shown = () => true;
  };
  end(0, "start");
  end(1, "goal");
  return list;
}

/** Painting walls on the small grid: press and drag; the first cell decides paint or erase. */
function paintable(S, G, cs, changed) {
  let painting = -1;
  const at = (e) => {
    const c = G.pxToCell(...logical(cs, e));
    if (painting < 0) painting = S.walls[c[0] * S.paintM + c[1]] ? 0 : 1;
    S.walls[c[0] * S.paintM + c[1]] = painting;
    S.dirty = true;
    changed(false);
  };
  cs.addEventListener("pointerdown", (e) => {
    if (!G.painted()) return;
    try { cs.setPointerCapture(e.pointerId); } catch (err) { /* synthetic events */ }
    painting = -1;
    at(e);
  });
  cs.addEventListener("pointermove", (e) => { if (painting >= 0) at(e); });
  cs.addEventListener("pointerup", () => { painting = -1; });
}

/** The C-space explorer: a tap on the C-space puts the configuration there. */
function tappable(S, G, cs, changed) {
  cs.addEventListener("pointerdown", (e) => {
    if (S.sweepObstacle >= 0) return;
    S.q = G.pxToQ(...logical(cs, e));
    changed(true);
  });
}
