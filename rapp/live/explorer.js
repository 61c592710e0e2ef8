// The explorers of chapters 4 and 5 (part 4 of the explorer module: the page and its controls).
// Workspace and C-space side by side, each half the width on a phone; the reader drags obstacles,
// the arm's joints or its point in C-space; the grid is recomputed on the next animation frame
// (never per pointer event). With `search` on, A* (rappLive.Search) runs on that grid or on a small
// grid the reader paints, and "move the arm" plays the path found; with `sweep` set to an
// obstacle, theta1 turns and that obstacle's C-space region is built column by column.

const CSS = `
.rapp-live{font:13px/1.35 system-ui,sans-serif;max-width:100%;color:#222}
.rapp-live .rl-row{display:flex;flex-wrap:nowrap;gap:8px;align-items:flex-start}
.rapp-live .rl-panel{position:relative;user-select:none;flex:1 1 0;min-width:0;max-width:300px}
.rapp-live canvas{display:block;border:1px solid #bbb;background:#fff;width:100%;height:auto;touch-action:none}
.rapp-live .rl-cs{display:grid;grid-template-columns:auto 1fr;column-gap:2px}
.rapp-live .rl-yt{position:relative;font-size:11px;text-align:right;min-width:1.6em}
.rapp-live .rl-yt span{position:absolute;right:0;line-height:1}
.rapp-live .rl-xt{grid-column:2;position:relative;font-size:11px;height:1.4em}
.rapp-live .rl-xt span{position:absolute;top:0;white-space:nowrap}
.rapp-live .rl-ctl{display:flex;flex-wrap:wrap;gap:6px 14px;align-items:center;margin:6px 0}
.rapp-live .rl-ctl button,.rapp-live .rl-ctl select{font:inherit;padding:4px 10px;min-height:32px}
.rapp-live .rl-ctl input[type=range]{min-height:32px;vertical-align:middle}
.rapp-live .rl-status{font-size:13px;margin:4px 0;min-height:2.7em}
.rapp-live .rl-note{font-size:12px;color:#555;margin:4px 0;max-width:640px}
.rapp-live .rl-cap{font-size:12px;color:#333;margin:2px 0}` + HANDLE_CSS;

function render({ model, el: host }) {
  const S = makeState(model), G = makeGeometry(S);
  const search = S.search, sweeping = S.sweepObstacle >= 0;
  const root = el("div", { class: "rapp-live", "data-rapp-live": search ? "astar" : sweeping ? "sweep" : "cspace" }, host);
  el("style", { text: CSS }, root);
  const ctl = el("div", { class: "rl-ctl" }, root);
  const row = el("div", { class: "rl-row" }, root);
  const wsPanel = el("div", { class: "rl-panel" }, row);
  const wsCap = el("div", { class: "rl-cap", text: workspaceCaption(S, G) }, wsPanel);
  const ws = el("canvas", { width: W, height: W, "data-rapp-drag": "workspace", role: "img",
    "aria-label": "the arm and its obstacles" }, wsPanel);
  const csPanel = el("div", { class: "rl-panel" }, row);
  const csCap = el("div", { class: "rl-cap" }, csPanel);
  const csBox = el("div", { class: "rl-cs" }, csPanel);
  const yt = el("div", { class: "rl-yt", "aria-hidden": "true" }, csBox);
  const cs = el("canvas", { width: W, height: W, "data-rapp-drag": "cspace", role: "img",
    "aria-label": "the C-space: θ₁ to the right, θ₂ up" }, csBox);
  const xt = el("div", { class: "rl-xt", "aria-hidden": "true" }, csBox);
  // Each label centred on its angle (tickAt), not spread evenly: "0" is at the canvas's middle.
  // The labels at the axis's ends keep inside it (aligned to the end, not centred past it).
  const shift = (f) => (f <= 0 ? "0" : f >= 1 ? "-100%" : "-50%");
  for (const [t, a] of Y_TICKS) {
    const f = tickAt(a, true);
    el("span", { text: t, style: `top:${(100 * f).toFixed(3)}%;transform:translateY(${shift(f)})` }, yt);
  }
  for (const [t, a] of X_TICKS) {
    const f = tickAt(a);
    el("span", { text: t, style: `left:${(100 * f).toFixed(3)}%;transform:translateX(${shift(f)})` }, xt);
  }
  const DPR = Math.min(3, Math.max(1, Math.round(window.devicePixelRatio || 1)));
  for (const cv of [ws, cs]) cv.width = cv.height = W * DPR;
  const status = el("div", { class: "rl-status", role: "status", "aria-live": "polite" }, root);
  el("div", {
    class: "rl-note",
    text: search
      ? "Computed in this page, in JavaScript: the C-space by rapp.occupancy's closed-form interval per link and obstacle, " +
        "and A* as rapp.astar runs it: unit steps to the 4 neighbours (across the seam on a wrapping axis), " +
        "f = g + w·h with the toroidal Manhattan heuristic GD1, ties to the larger g, then the smaller cell number; " +
        "blue: closed set, yellow: open list; orange-red squares: where the path crosses the seam. tests/test_live.py checks both against rapp."
      : sweeping
        ? "θ₁ turns from −π to π; at each θ₁ the page paints the column of θ₂ at which link 2 (or link 1) touches the obstacle, " +
          "from the closed-form interval rapp.occupancy uses. The region grows column by column into the obstacle's C-space image."
        : "Computed in this page, in JavaScript, on every move: for each link and obstacle the closed-form interval of " +
          "joint angles at which the link touches it (rapp.occupancy), painted onto the grid; tests/test_live.py checks " +
          "the grid against rapp.occupancy. The dashed orange-red border is the seam: θ = −π and θ = π are the same angle.",
  }, root);

  // ---- controls
  const L = G.L;
  function slider(label, min, max, step, value, on, parent) {
    const lab = el("label", {}, parent || ctl);
    lab.append(label + " ");
    const inp = el("input", { type: "range", min, max, step, value, "aria-label": label }, lab);
    const out = el("span", { text: String(value), "aria-hidden": "true" }, lab);
    inp.addEventListener("input", () => { out.textContent = inp.value; on(+inp.value); schedule(); });
    inp.addEventListener("change", () => sync());
    return inp;
  }
  function button(text, on) {
    const b = el("button", { type: "button", text }, ctl);
    b.addEventListener("click", on);
    return b;
  }
  // The arm's controls; hidden while the A* explorer searches a painted grid, which has no arm.
  const armCtl = el("span", { class: "rl-ctl", style: "margin:0" }, ctl);
  slider("link 1 (m)", 0.3, 1.5, 0.05, L[0], (v) => { L[0] = v; S.dirty = true; }, armCtl);
  slider("link 2 (m)", 0.3, 1.5, 0.05, L[1], (v) => { L[1] = v; S.dirty = true; }, armCtl);
  slider("cells M", 24, 180, 2, S.M, (v) => { S.M = v; S.dirty = true; }, armCtl);
  let playBtn = null, moveBtn = null, sweepBtn = null;
  if (search) {
    const sel = el("select", { "aria-label": "the grid A* searches" }, ctl);
    [["cspace", "grid: the C-space"], ["paint", "grid: paint walls (" + S.paintM + " × " + S.paintM + ")"]].forEach(([v, t]) => {
      const o = el("option", { value: v, text: t }, sel);
      if (v === S.source) o.selected = true;
    });
    sel.addEventListener("change", () => switchSource(sel.value));
    slider("weight w", 1, 3, 0.25, S.weight, (v) => { S.weight = v; S.dirty = true; });
    playBtn = button("▶ play", () => {
      flush();
      stopMotion();
      if (!S.playing && S.run.status !== "running") restartSearch();
      S.playing = !S.playing;
      playBtn.textContent = S.playing ? "❚❚ pause" : "▶ play";
      tick();
    });
    button("step", () => {
      flush();
      stopMotion();
      if (S.run.status !== "running") restartSearch();
      S.playing = false;
      playBtn.textContent = "▶ play";
      S.run.step(1);
      draw();
    });
    button("to the end", () => { flush(); S.playing = false; playBtn.textContent = "▶ play"; S.run.step(Infinity); draw(); });
    slider("speed", 1, 40, 1, S.perFrame, (v) => { S.perFrame = v; });
    moveBtn = button("▶ move the arm", () => {
      flush();
      if (S.motion >= 0 && motionTimer) { stopMotion(); draw(); return; }
      if (S.run.status !== "running" || S.playing) { S.playing = false; playBtn.textContent = "▶ play"; S.run.step(Infinity); }
      if (S.run.status !== "found") { draw(); return; }
      S.motion = 0;
      moveBtn.textContent = "❚❚ stop the arm";
      motionStep();
    });
  }
  if (sweeping) {
    sweepBtn = button("▶ sweep θ₁", () => {
      flush();
      if (sweepTimer) { stopSweep(); draw(); return; }
      S.sweep = 0;
      sweepBtn.textContent = "❚❚ pause";
      sweepStep();
    });
    // It opens half built, at theta1 = 0: the picture shows what the sweep does before it runs.
    S.sweep = Math.floor(S.M / 2);
    const col = slider("θ₁ column", 1, S.M, 1, sweepSliderValue(S), (v) => { stopSweep(); S.sweep = Math.min(sweepFromSlider(v), G.gridM() - 1); });
    S.sweepSlider = col;
  }

  // ---- handles
  const P = { wsPanel, csPanel, ws, cs };
  const handles = makeHandles(S, G, P, (final) => { schedule(); if (final) sync(); });
  if (search) paintable(S, G, cs, (final) => { schedule(); if (final) sync(); });
  else tappable(S, G, cs, (final) => { schedule(); if (final) sync(); });

  function switchSource(v) {
    // Keep each grid's start and goal: the reader comes back to where they were.
    S.ends[S.source] = [S.start.slice(), S.goal.slice()];
    S.source = v;
    stopMotion();
    if (S.ends[v]) { S.start = S.ends[v][0].slice(); S.goal = S.ends[v][1].slice(); }
    S.dirty = true;
    S.snapEnds = true;
    schedule();
    sync();
  }

  // ---- computation (on an animation frame only)
  function recompute() {
    const t0 = performance.now();
    const M = G.gridM();
    if (G.painted()) {
      S.occ = S.walls.slice();
      S.layers = null;
    } else {
      S.layers = R.occupancyOf(R.parseScenario(S.scenario), M, true);
      S.occ = new Uint8Array(M * M);
      for (const lay of S.layers) for (let i = 0; i < S.occ.length; i++) S.occ[i] |= lay[i];
    }
    if (search) {
      S.start = S.start.map((v) => Math.min(M - 1, Math.max(0, v)));
      S.goal = S.goal.map((v) => Math.min(M - 1, Math.max(0, v)));
      S.snapped = "";
      if (S.snapEnds) {
        // After the menu switched grids: an end on a wall moves to the nearest free cell.
        S.snapEnds = false;
        for (const name of ["start", "goal"]) {
          const c = nearestFree(S.occ, M, S[name]);
          if (c && (c[0] !== S[name][0] || c[1] !== S[name][1])) {
            S.snapped += `The ${name} was on a wall; it moved to the nearest free cell (${c[0]}, ${c[1]}). `;
            S[name] = c;
          }
        }
        S.snapped = S.snapped.trim();
      }
      S.motion = -1;
      restartSearch();
      if (!S.playing) S.run.step(Infinity);
    }
    if (sweeping && S.sweep > M - 1) S.sweep = M - 1;
    S.lastMs = performance.now() - t0;
    S.frame += 1;
    root.setAttribute("data-rapp-frame", String(S.frame));
    root.setAttribute("data-rapp-ms", S.lastMs.toFixed(2));
  }
  function restartSearch() {
    const M = G.gridM();
    S.run = new R.Search(S.occ, [M, M], S.start, S.goal, { weight: S.weight, wraps: [true, true], buffers: S.buffers });
  }

  // ---- drawing
  const off = document.createElement("canvas");
  let lastStatus = "";
  function draw() {
    const M = G.gridM();
    csCap.textContent = G.painted()
      ? "a " + M + " × " + M + " grid, both axes wrap (drag to paint or erase walls)"
      : sweeping ? "obstacle " + (S.sweepObstacle + 1) + " in C-space, built as θ₁ turns"
        : "C-space (" + M + " × " + M + " cells)";
    wsPanel.style.display = armCtl.style.display = G.painted() ? "none" : "";
    xt.style.visibility = yt.style.visibility = G.painted() ? "hidden" : "";
    const crossings = drawCspace(S, G, ctx2d(cs, DPR), off);
    drawWorkspace(S, G, ctx2d(ws, DPR));
    for (const x of handles) {
      const shown = x.shown();
      x.h.style.display = shown ? "" : "none";
      if (shown) x.place(x.where());
    }
    if (moveBtn) moveBtn.disabled = G.painted();
    if (S.sweepSlider) {
      // The slider shows the column the status line names (also after "cells M" shrank the grid).
      S.sweepSlider.max = String(G.gridM());
      S.sweepSlider.value = String(sweepSliderValue(S));
      S.sweepSlider.nextSibling.textContent = S.sweepSlider.value;
    }
    wsCap.textContent = workspaceCaption(S, G);
    root.setAttribute("data-rapp-motion", String(S.motion));
    root.setAttribute("data-rapp-sweep", String(S.sweep));
    const txt = statusText(S, G, crossings);
    // The live region speaks only when the sentence changes.
    if (txt !== lastStatus) { status.textContent = txt; lastStatus = txt; }
  }

  // ---- the frame loop: at most one recompute and one drawing per animation frame
  function flush() {
    if (S.dirty) { S.dirty = false; recompute(); }
  }
  let pending = false;
  function schedule() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => { pending = false; flush(); draw(); });
  }
  function tick() {
    if (!S.playing) return;
    if (S.run.status === "running") S.run.step(S.perFrame);
    draw();
    if (S.run.status !== "running") {
      S.playing = false;
      playBtn.textContent = "▶ play";
      return;
    }
    requestAnimationFrame(tick);
  }
  // The arm moves along the path, one cell every 40 ms (about 4 s for 100 steps).
  let motionTimer = null;
  function motionStep() {
    motionTimer = null;
    if (S.motion < 0 || !S.run.path) return;
    draw();
    if (S.motion >= S.run.path.length - 1) { moveBtn.textContent = "▶ move the arm"; return; }
    S.motion += 1;
    motionTimer = setTimeout(motionStep, 40);
  }
  function stopMotion() {
    if (motionTimer) clearTimeout(motionTimer);
    motionTimer = null;
    S.motion = -1;
    if (moveBtn) moveBtn.textContent = "▶ move the arm";
  }
  let sweepTimer = null;
  function sweepStep() {
    sweepTimer = null;
    draw();
    if (S.sweep >= G.gridM() - 1) { sweepBtn.textContent = "▶ sweep θ₁"; return; }
    S.sweep += 1;
    sweepTimer = setTimeout(sweepStep, Math.max(15, 4000 / G.gridM()));
  }
  function stopSweep() {
    if (sweepTimer) clearTimeout(sweepTimer);
    sweepTimer = null;
    if (sweepBtn) sweepBtn.textContent = "▶ sweep θ₁";
  }
  // In JupyterLab the Python side sees where the reader left things; the static book has no
  // kernel, so saving may fail there, harmlessly.
  function sync() {
    try {
      model.set("q", S.q.slice());
      model.set("scenario", clone(S.scenario));
      model.set("cells", S.M);
      if (search) {
        model.set("start", S.start.slice()); model.set("goal", S.goal.slice());
        model.set("weight", S.weight); model.set("source", S.source);
      }
      const r = model.save_changes();
      if (r && r.catch) r.catch(() => {});
    } catch (e) { /* no kernel */ }
  }
  recompute();
  draw();
  // Sizes are known only once the element is in the page: place the handles again then.
  requestAnimationFrame(() => draw());
  if (typeof ResizeObserver !== "undefined") new ResizeObserver(() => draw()).observe(root);
  return () => { stopMotion(); stopSweep(); S.playing = false; };
}

export default { render };
