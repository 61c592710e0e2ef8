// Drawing (part 2 of the explorer module): the C-space image, the path and its seam crossings,
// the workspace with the obstacles, the arm, the goal's ghost and chapter 4's sweep. Reads the
// state, never changes it.

const ctx2d = (cv, dpr) => {
  const x = cv.getContext("2d");
  x.setTransform(dpr, 0, 0, dpr, 0, 0);
  return x;
};

/** Draw the C-space; returns the path's seam crossings per axis. */
function drawCspace(S, G, c, off) {
  const M = G.gridM(), occ = S.occ, X = S.run, layers = S.layers;
  const sweepK = S.sweepObstacle;
  off.width = M; off.height = M;
  const ctx0 = off.getContext("2d"), img = ctx0.createImageData(M, M), d = img.data;
  for (let i = 0; i < M; i++) for (let j = 0; j < M; j++) {
    const k = i * M + j, p = ((M - 1 - j) * M + i) * 4;
    let col = [255, 255, 255];
    if (sweepK >= 0) {
      // The sweep: only columns theta1 has passed, only the swept obstacle.
      if (layers && i <= S.sweep && layers[sweepK][k]) col = RGB[sweepK % RGB.length].map((v) => 0.55 * v + 40);
    } else if (occ[k]) {
      col = [150, 150, 150];
      if (layers) for (let o = 0; o < layers.length; o++) if (layers[o][k]) { col = RGB[o % RGB.length].map((v) => 0.55 * v + 40); break; }
    } else if (X && X.isClosed(k)) col = [170, 205, 240];
    else if (X && X.isOpen(k)) col = [240, 228, 66];
    d[p] = col[0]; d[p + 1] = col[1]; d[p + 2] = col[2]; d[p + 3] = 255;
  }
  ctx0.putImageData(img, 0, 0);
  c.imageSmoothingEnabled = false;
  c.clearRect(0, 0, W, W);
  c.drawImage(off, 0, 0, W, W);
  // The seam: the square's edges are one circle per axis.
  c.save();
  c.strokeStyle = "#D55E00"; c.lineWidth = 3; c.setLineDash([6, 4]);
  c.strokeRect(1.5, 1.5, W - 3, W - 3);
  c.restore();
  if (sweepK >= 0 && S.sweep >= 0) {
    const x = (S.sweep + 0.5) * G.cellPx();
    c.strokeStyle = "#000"; c.lineWidth = 1.5; c.beginPath(); c.moveTo(x, 0); c.lineTo(x, W); c.stroke();
  }
  const crossings = [0, 0];
  if (X && X.path) {
    const cells = R.toCells(X.path, M), cp = G.cellPx();
    c.strokeStyle = "#000"; c.lineWidth = 2.5; c.beginPath();
    for (let k = 0; k < cells.length; k++) {
      const p = G.cellToPx(cells[k]);
      const di = cells[k][0] - (k ? cells[k - 1][0] : 0), dj = cells[k][1] - (k ? cells[k - 1][1] : 0);
      if (k > 0 && (Math.abs(di) > 1 || Math.abs(dj) > 1)) {
        crossings[Math.abs(di) > 1 ? 0 : 1] += 1;
        // Leave through one edge and come back through the opposite one.
        const q = G.cellToPx(cells[k - 1]);
        const ex = di > 1 ? -cp : di < -1 ? cp : 0, ey = dj > 1 ? cp : dj < -1 ? -cp : 0;
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
    if (S.motion >= 0) {
      // The marker of the moving arm on its C-space path.
      const p = G.cellToPx(cells[Math.min(S.motion, cells.length - 1)]);
      c.fillStyle = "#E69F00"; c.strokeStyle = "#000"; c.lineWidth = 2;
      c.beginPath(); c.arc(p[0], p[1], 7, 0, 2 * Math.PI); c.fill(); c.stroke();
    }
  }
  if (X && X.current >= 0 && X.status === "running") {
    const p = G.cellToPx([(X.current / M) | 0, X.current % M]), cp = G.cellPx();
    c.strokeStyle = "#000"; c.lineWidth = 2; c.strokeRect(p[0] - cp / 2, p[1] - cp / 2, cp, cp);
  }
  if (!S.search && sweepK < 0) {
    // The configuration: a cross on the cell nearest to q.
    const p = G.cellToPx(G.qCell(S.q));
    c.strokeStyle = "#000"; c.lineWidth = 2; c.beginPath();
    c.moveTo(p[0] - 9, p[1]); c.lineTo(p[0] + 9, p[1]); c.moveTo(p[0], p[1] - 9); c.lineTo(p[0], p[1] + 9); c.stroke();
  }
  return crossings;
}

function drawArm(w, J, colour, width, dash) {
  w.save();
  w.strokeStyle = colour; w.lineWidth = width; w.lineCap = "round"; w.setLineDash(dash || []);
  w.beginPath(); w.moveTo(J[0][0], J[0][1]); w.lineTo(J[1][0], J[1][1]); w.lineTo(J[2][0], J[2][1]); w.stroke();
  w.restore();
}

/** Draw the workspace; returns the configuration the arm is drawn at and whether it collides. */
function drawWorkspace(S, G, w) {
  const M = G.gridM();
  w.clearRect(0, 0, W, W);
  w.strokeStyle = "#ddd"; w.setLineDash([3, 3]); w.beginPath();
  const o = G.toPx([0, 0]), rpx = ((G.L[0] + G.L[1]) / G.reach()) * (W / 2);
  w.arc(o[0], o[1], rpx, 0, 2 * Math.PI); w.stroke(); w.setLineDash([]);
  S.scenario.obstacles.forEach((ob, k) => {
    const faded = S.sweepObstacle >= 0 && k !== S.sweepObstacle;
    w.fillStyle = faded ? "#dddddd99" : PALETTE[k % PALETTE.length] + "99";
    w.strokeStyle = faded ? "#bbb" : PALETTE[k % PALETTE.length];
    w.beginPath();
    if (ob.type === "circle") {
      const p = G.toPx(ob.center);
      w.arc(p[0], p[1], (ob.radius / G.reach()) * (W / 2), 0, 2 * Math.PI);
    } else {
      const v = R.parseScenario({ arm: { link_lengths: [1, 1] }, obstacles: [ob] }).obstacles[0].v;
      v.forEach((pt, i) => { const p = G.toPx(pt); if (i) w.lineTo(p[0], p[1]); else w.moveTo(p[0], p[1]); });
      w.closePath();
    }
    w.fill(); w.stroke();
  });
  let q = S.q, hit = false;
  const X = S.run;
  if (S.search && !G.painted()) {
    // The A* explorer: the arm at the start, or moving along the path; the goal as a ghost.
    const cells = X && X.path ? R.toCells(X.path, M) : null;
    q = S.motion >= 0 && cells ? G.cellQ(cells[Math.min(S.motion, cells.length - 1)]) : G.cellQ(S.start);
    drawArm(w, G.joints(G.cellQ(S.goal)).map(G.toPx), "#D55E0088", 5, [6, 5]);
    hit = S.motion < 0 && X && X.blockedEnd === "start";
  } else if (S.sweepObstacle >= 0 && S.sweep >= 0) {
    // The sweep: link 2 at every theta2 of this column that hits the obstacle, faint red.
    q = [G.cellAngle(S.sweep), S.q[1]];
    const lay = S.layers[S.sweepObstacle], e = G.joints(q)[1];
    w.strokeStyle = "#D55E0066"; w.lineWidth = 2;
    for (let j = 0; j < M; j++) {
      if (!lay[S.sweep * M + j]) continue;
      const a = q[0] + G.cellAngle(j), tip = [e[0] + G.L[1] * Math.cos(a), e[1] + G.L[1] * Math.sin(a)];
      const p0 = G.toPx(e), p1 = G.toPx(tip);
      w.beginPath(); w.moveTo(p0[0], p0[1]); w.lineTo(p1[0], p1[1]); w.stroke();
    }
    const ci = G.qCell(q);
    hit = !!lay[ci[0] * M + ci[1]];
  } else if (!S.search) {
    const ci = G.qCell(q);
    hit = !!S.occ[ci[0] * M + ci[1]];
  }
  const J = G.joints(q).map(G.toPx);
  drawArm(w, J, hit ? "#D55E00" : "#222", 5);
  w.fillStyle = "#222"; w.beginPath(); w.arc(J[0][0], J[0][1], 5, 0, 2 * Math.PI); w.fill();
  return { q, J };
}
