// rapp's C-space and A* in the browser: the book's definitions, ported from rapp/cspace.py and
// rapp/search.py so that an explorer can recompute them on every drag, with no kernel.
//
// occupancy(scenario, M): the closed-form intervals of rapp.occupancy. For a 2-link arm, link 1
// (the first) starts at the base and link 2 at the elbow, which depends on theta1 only; from a
// fixed base point P the absolute directions in which a link of length L touches a disc or a
// convex polygon form ONE interval, computed in closed form (_circle_hits, _polygon_hits) and
// painted onto the joint's axis (_paint). The work is per row of the prefix grid and obstacle.
//
// astar(occupied, shape, start, goal): A* of rapp.astar with the toroidal Manhattan heuristic
// GD1, f = g + w h, ties to the larger g, then to the smaller cell number: the same total order,
// so the same expansions and the same path.
//
// Loaded as a classic script it defines window.rappLive; inside an ES module (the anywidget
// explorers) it does the same, through globalThis.
(function (root) {
  "use strict";
  var TWO_PI = 2 * Math.PI;
  var TINY = 2.2250738585072014e-308; // np.finfo(float).tiny

  function fail(msg) {
    throw new Error("rappLive: " + msg);
  }

  // ------------------------------------------------------------------ scenario
  // The scenario-file format of rapp/scenario.py: arm.link_lengths, arm.joint_limits (null or one
  // [lo, hi] or null per joint), obstacles typed circle / rectangle / polygon, units.angle.
  function vertices(ob, k) {
    var v;
    if (ob.type === "polygon") {
      v = ob.vertices.map(function (p) { return [+p[0], +p[1]]; });
    } else {
      var a = (ob.angle || 0) * k, c = Math.cos(a), s = Math.sin(a);
      var w = +ob.width, h = +ob.height, cx = +ob.corner[0], cy = +ob.corner[1];
      v = [[0, 0], [w, 0], [w, h], [0, h]].map(function (p) {
        return [cx + (p[0] * c + p[1] * -s), cy + (p[0] * s + p[1] * c)];
      });
    }
    // rapp.Polygon stores the vertices counter-clockwise: reversed when the turns add up negative.
    var n = v.length, cross = 0;
    for (var i = 0; i < n; i++) {
      var a0 = v[i], a1 = v[(i + 1) % n], a2 = v[(i + 2) % n];
      var ex = a1[0] - a0[0], ey = a1[1] - a0[1], fx = a2[0] - a1[0], fy = a2[1] - a1[1];
      cross += ex * fy - ey * fx;
    }
    if (cross < 0) v.reverse();
    return v;
  }

  function parseScenario(scenario) {
    if (!scenario || !scenario.arm || !scenario.arm.link_lengths) fail("scenario needs arm.link_lengths");
    var L = scenario.arm.link_lengths.map(Number);
    if (L.length !== 2) fail("arm.link_lengths: the live explorers handle 2 links, got " + L.length);
    var k = scenario.units && scenario.units.angle === "deg" ? Math.PI / 180 : 1;
    var lim = scenario.arm.joint_limits || [null, null];
    var limits = [0, 1].map(function (i) {
      return lim[i] ? [lim[i][0] * k, lim[i][1] * k] : null;
    });
    var obs = (scenario.obstacles || []).map(function (ob, i) {
      if (ob.type === "circle") return { kind: "circle", cx: +ob.center[0], cy: +ob.center[1], r: +ob.radius };
      if (ob.type === "rectangle" || ob.type === "polygon") return { kind: "polygon", v: vertices(ob, k) };
      fail("obstacles[" + i + "].type must be circle, rectangle or polygon");
    });
    return { L: L, limits: limits, obstacles: obs };
  }

  // ------------------------------------------------------------------ grid axes (rapp.JointGrid)
  function axis(limit, M) {
    var ax = new Float64Array(M), step;
    if (!limit) {
      for (var i = 0; i < M; i++) ax[i] = (TWO_PI * i) / M - Math.PI;
      step = TWO_PI / M;
    } else {
      step = (limit[1] - limit[0]) / (M - 1);
      for (var j = 0; j < M; j++) ax[j] = limit[0] + j * step; // np.linspace
      ax[M - 1] = limit[1];
    }
    return { ax: ax, step: step, wraps: !limit };
  }

  // ------------------------------------------------------------------ closed-form intervals
  // Directions from P = (px[r], py[r]) in which a link of length L touches a disc: the interval
  // [start, start + width] (mod 2 pi); width < 0 never, width >= 2 pi always (rapp.cspace._circle_hits).
  function circleHits(px, py, L, ob, start, width) {
    var r = ob.r;
    for (var k = 0; k < px.length; k++) {
      var vx = ob.cx - px[k], vy = ob.cy - py[k];
      var d2 = vx * vx + vy * vy, d = Math.sqrt(d2);
      if (L < d - r) { start[k] = 0; width[k] = -1; continue; }
      var t = Math.sqrt(Math.max((d - r) * (d + r), 0));
      var h;
      if (d2 <= r * r) h = TWO_PI; // P in the disc: every direction
      else if (L >= t) h = Math.atan2(r, t); // the link reaches the tangent point
      else h = 2 * Math.atan(Math.sqrt(Math.max(L + r - d, 0) * Math.max(d + r - L, 0) /
        ((d + L + r) * Math.max(d + L - r, TINY)))); // only the tip enters: half-angle formula
      start[k] = Math.atan2(vy, vx) - Math.min(h, Math.PI);
      width[k] = 2 * h;
    }
  }

  // The same for a convex polygon (rapp.cspace._polygon_hits): the extreme directions are among
  // the vertices within L and the crossings of the edges with the circle of radius L about P.
  function polygonHits(px, py, L, ob, start, width) {
    var v = ob.v, n = v.length, k, j;
    var ex = new Float64Array(n), ey = new Float64Array(n), ee = new Float64Array(n);
    var vmax = 0, pmax = 0, cx = 0, cy = 0;
    for (j = 0; j < n; j++) {
      ex[j] = v[(j + 1) % n][0] - v[j][0];
      ey[j] = v[(j + 1) % n][1] - v[j][1];
      ee[j] = ex[j] * ex[j] + ey[j] * ey[j];
      vmax = Math.max(vmax, Math.abs(v[j][0]), Math.abs(v[j][1]));
      cx += v[j][0];
      cy += v[j][1];
    }
    cx /= n;
    cy /= n;
    var rad2 = 0;
    for (j = 0; j < n; j++) rad2 = Math.max(rad2, (v[j][0] - cx) * (v[j][0] - cx) + (v[j][1] - cy) * (v[j][1] - cy));
    var rad = Math.sqrt(rad2);
    for (k = 0; k < px.length; k++) pmax = Math.max(pmax, Math.abs(px[k]), Math.abs(py[k]));
    var tol = 1e-12 * Math.max(1, L, vmax, pmax);
    var cxs = new Float64Array(3 * n), cys = new Float64Array(3 * n), oks = new Uint8Array(3 * n);
    for (k = 0; k < px.length; k++) {
      start[k] = 0;
      width[k] = -1;
      var P0 = px[k], P1 = py[k];
      if (!(Math.hypot(P0 - cx, P1 - cy) <= L + rad + 2 * tol)) continue;
      var inside = true;
      for (j = 0; j < n; j++) {
        var wx = v[j][0] - P0, wy = v[j][1] - P1;
        if (!(ey[j] * wx - ex[j] * wy >= -tol * Math.sqrt(ee[j]))) inside = false;
        var w2 = wx * wx + wy * wy;
        cxs[j] = wx; cys[j] = wy; oks[j] = w2 <= (L + tol) * (L + tol) ? 1 : 0;
        var b = wx * ex[j] + wy * ey[j];
        var disc = b * b - ee[j] * (w2 - L * L);
        var root = Math.sqrt(Math.max(disc, 0)), slack = tol / Math.sqrt(ee[j]);
        for (var q = 0; q < 2; q++) {
          var sg = q === 0 ? -1 : 1, s = (-b + sg * root) / ee[j];
          var ok = disc >= 0 && s >= -slack && s <= 1 + slack;
          s = Math.min(Math.max(s, 0), 1);
          var c = (q + 1) * n + j;
          cxs[c] = wx + s * ex[j]; cys[c] = wy + s * ey[j]; oks[c] = ok ? 1 : 0;
        }
      }
      var ref = -1;
      for (j = 0; j < 3 * n; j++) if (oks[j]) { ref = j; break; }
      if (inside) {
        var r0 = ref < 0 ? 0 : ref;
        start[k] = ref < 0 ? 0 : Math.atan2(cys[r0], cxs[r0]);
        width[k] = TWO_PI;
      }
      if (ref < 0) continue;
      var rx = cxs[ref], ry = cys[ref], lo = Infinity, hi = -Infinity;
      for (j = 0; j < 3 * n; j++) {
        if (!oks[j]) continue;
        var rel = Math.atan2(rx * cys[j] - ry * cxs[j], rx * cxs[j] + ry * cys[j]);
        if (rel < lo) lo = rel;
        if (rel > hi) hi = rel;
      }
      start[k] = Math.atan2(ry, rx) + lo;
      width[k] = inside ? TWO_PI : hi - lo;
    }
  }

  function pymod(a, b) {
    var m = a % b;
    return m < 0 ? m + b : m;
  }

  // Cells of one joint axis covered by an interval [s, s + w] (mod 2 pi), row by row, OR-ed into
  // out[row * M + col] (rapp.cspace._paint: the interval cut at multiples of 2 pi into index ranges).
  function paint(starts, widths, A, out, rowStride, colStride, M) {
    var ax = A.ax, lo = ax[0], step = A.step;
    var periods = Math.floor((ax[M - 1] - lo) / TWO_PI) + 2;
    for (var r = 0; r < starts.length; r++) {
      var w = widths[r];
      if (!(w >= 0)) continue;
      var base = r * rowStride;
      if (periods > M) {
        for (var c0 = 0; c0 < M; c0++) if (pymod(ax[c0] - starts[r], TWO_PI) <= w) out[base + c0 * colStride] = 1;
        continue;
      }
      var f = pymod(starts[r] - lo, TWO_PI);
      for (var p = -1; p < periods - 1; p++) {
        var a = f + p * TWO_PI;
        var first = Math.max(Math.ceil(a / step), 0), last = Math.min(Math.floor((a + w) / step), M - 1);
        for (var c = first; c <= last; c++) out[base + c * colStride] = 1;
      }
    }
  }

  // ------------------------------------------------------------------ occupancy
  function occupancyOf(parsed, M, perObstacle) {
    var M0 = Array.isArray(M) ? M[0] : M, M1 = Array.isArray(M) ? M[1] : M;
    var A0 = axis(parsed.limits[0], M0), A1 = axis(parsed.limits[1], M1);
    var occ = new Uint8Array(M0 * M1);
    var obs = parsed.obstacles, L0 = parsed.L[0], L1 = parsed.L[1];
    // Link 1: base point at the origin, one row; its hits span every theta2.
    var row0 = new Uint8Array(M0);
    var s1 = new Float64Array(1), w1 = new Float64Array(1), zero = new Float64Array(1);
    // Link 2: base point the elbow, one row per theta1; relative angle = absolute - theta1.
    var ex = new Float64Array(M0), ey = new Float64Array(M0);
    for (var i = 0; i < M0; i++) {
      ex[i] = 0 + L0 * Math.cos(A0.ax[i]);
      ey[i] = 0 + L0 * Math.sin(A0.ax[i]);
    }
    var s2 = new Float64Array(M0), w2 = new Float64Array(M0);
    var layers = perObstacle ? [] : null;
    for (var o = 0; o < obs.length; o++) {
      var hits = obs[o].kind === "circle" ? circleHits : polygonHits;
      var target = perObstacle ? new Uint8Array(M0 * M1) : occ;
      var r0 = perObstacle ? new Uint8Array(M0) : row0;
      hits(zero, zero, L0, obs[o], s1, w1);
      paint(s1, w1, A0, r0, 0, 1, M0);
      hits(ex, ey, L1, obs[o], s2, w2);
      for (i = 0; i < M0; i++) s2[i] -= A0.ax[i];
      paint(s2, w2, A1, target, M1, 1, M1);
      if (perObstacle) {
        for (i = 0; i < M0; i++) if (r0[i]) target.fill(1, i * M1, (i + 1) * M1);
        layers.push(target);
      }
    }
    if (perObstacle) return layers;
    for (i = 0; i < M0; i++) if (row0[i]) occ.fill(1, i * M1, (i + 1) * M1);
    return occ;
  }

  /** The M x M occupancy grid of a scenario, flattened in C order (1 = collides). */
  function occupancy(scenario, M) {
    return Array.from(occupancyOf(parseScenario(scenario), M, false));
  }

  // ------------------------------------------------------------------ A*
  // A search that can be run a few expansions at a time (the explorer animates it) or to the end
  // (astar). State: g (-1 = closed or blocked), parent, a binary heap ordered by (f, -g, cell).
  function Search(occupied, shape, start, goal, opts) {
    opts = opts || {};
    var M0 = shape[0], M1 = shape[1], size = M0 * M1;
    var wraps = opts.wraps === undefined ? [true, true] : opts.wraps;
    if (typeof wraps === "boolean") wraps = [wraps, wraps];
    var weight = opts.weight === undefined ? 1 : opts.weight;
    if (!(weight >= 1)) fail("heuristic weight must be >= 1");
    var s = start[0] * M1 + start[1], t = goal[0] * M1 + goal[1];
    [start, goal].forEach(function (c, k) {
      if (!(c[0] >= 0 && c[0] < M0 && c[1] >= 0 && c[1] < M1)) fail((k ? "goal" : "start") + " is outside the grid");
    });
    this.blockedEnd = occupied[s] ? "start" : occupied[t] ? "goal" : null;
    // GD1 per axis: d = |c - goal|, min(d, M - d) on a wrapping axis.
    var h0 = new Float64Array(M0), h1 = new Float64Array(M1);
    for (var a = 0; a < M0; a++) { var d0 = Math.abs(a - goal[0]); h0[a] = wraps[0] && M0 - d0 < d0 ? M0 - d0 : d0; }
    for (var b = 0; b < M1; b++) { var d1 = Math.abs(b - goal[1]); h1[b] = wraps[1] && M1 - d1 < d1 ? M1 - d1 : d1; }
    this.g = new Int32Array(size);
    this.parent = new Int32Array(size).fill(-1);
    for (var i = 0; i < size; i++) this.g[i] = occupied[i] ? -1 : 2147483647;
    this.closed = new Uint8Array(size);
    this.M0 = M0; this.M1 = M1; this.size = size; this.wraps = wraps; this.weight = weight;
    this.h0 = h0; this.h1 = h1; this.s = s; this.t = t;
    this.hf = new Float64Array(1024); this.hk = new Float64Array(1024); this.len = 0;
    this.expansions = 0; this.status = "running"; this.path = null; this.current = -1;
    if (this.blockedEnd) { this.status = "blocked"; return; }
    this.g[s] = 0;
    this.push(weight * (h0[start[0]] + h1[start[1]]), s);
    if (s === t) { this.status = "found"; this.path = [s]; }
  }

  Search.prototype.less = function (i, j) {
    return this.hf[i] < this.hf[j] || (this.hf[i] === this.hf[j] && this.hk[i] < this.hk[j]);
  };

  Search.prototype.push = function (f, key) {
    if (this.len === this.hf.length) {
      var nf = new Float64Array(2 * this.len), nk = new Float64Array(2 * this.len);
      nf.set(this.hf); nk.set(this.hk); this.hf = nf; this.hk = nk;
    }
    var i = this.len++, hf = this.hf, hk = this.hk;
    while (i > 0) {
      var p = (i - 1) >> 1;
      if (hf[p] < f || (hf[p] === f && hk[p] < key)) break;
      hf[i] = hf[p]; hk[i] = hk[p]; i = p;
    }
    hf[i] = f; hk[i] = key;
  };

  Search.prototype.pop = function () {
    var hf = this.hf, hk = this.hk, top = hk[0];
    var n = --this.len;
    if (n > 0) {
      var xf = hf[n], xk = hk[n], i = 0;
      for (;;) {
        var j = 2 * i + 1;
        if (j >= n) break;
        var r = j + 1;
        if (r < n && (hf[r] < hf[j] || (hf[r] === hf[j] && hk[r] < hk[j]))) j = r;
        if (hf[j] < xf || (hf[j] === xf && hk[j] < xk)) { hf[i] = hf[j]; hk[i] = hk[j]; i = j; } else break;
      }
      hf[i] = xf; hk[i] = xk;
    }
    // key = cell - g * size: the cell is key mod size.
    return ((top % this.size) + this.size) % this.size;
  };

  /** Run at most k expansions (Infinity: to the end). Returns the status. */
  Search.prototype.step = function (k) {
    var M0 = this.M0, M1 = this.M1, size = this.size, g = this.g, closed = this.closed;
    var w = this.weight, h0 = this.h0, h1 = this.h1, wr0 = this.wraps[0], wr1 = this.wraps[1];
    var done = 0, nb = [0, 0, 0, 0];
    while (this.status === "running" && done < k) {
      if (this.len === 0) { this.status = "unreachable"; break; }
      var u = this.pop();
      if (closed[u]) continue;
      if (u === this.t) {
        this.status = "found";
        var path = [u];
        while (path[path.length - 1] !== this.s) path.push(this.parent[path[path.length - 1]]);
        this.path = path.reverse();
        break;
      }
      closed[u] = 1;
      this.current = u;
      this.expansions++;
      done++;
      var gv = g[u] + 1, i0 = (u / M1) | 0, i1 = u - i0 * M1, m = 0;
      if (i0 + 1 < M0) nb[m++] = u + M1; else if (wr0) nb[m++] = i1;
      if (i0 > 0) nb[m++] = u - M1; else if (wr0) nb[m++] = (M0 - 1) * M1 + i1;
      if (i1 + 1 < M1) nb[m++] = u + 1; else if (wr1) nb[m++] = u - i1;
      if (i1 > 0) nb[m++] = u - 1; else if (wr1) nb[m++] = u + M1 - 1;
      for (var q = 0; q < m; q++) {
        var v = nb[q];
        if (closed[v] || g[v] < 0 || gv >= g[v]) continue;
        g[v] = gv;
        this.parent[v] = u;
        var v0 = (v / M1) | 0;
        this.push(gv + w * (h0[v0] + h1[v - v0 * M1]), v - gv * size);
      }
    }
    return this.status;
  };

  /** Open cells: reached, not closed. */
  Search.prototype.openCells = function () {
    var out = [];
    for (var i = 0; i < this.size; i++) if (this.g[i] >= 0 && this.g[i] < 2147483647 && !this.closed[i]) out.push(i);
    return out;
  };

  function toCells(flat, M1) {
    return flat.map(function (c) { return [(c / M1) | 0, c % M1]; });
  }

  /** The path of rapp.astar, start to goal, as [i, j] cells; throws when there is none. */
  function astar(occupied, shape, start, goal, opts) {
    var S = new Search(occupied, shape, start, goal, opts);
    S.step(Infinity);
    if (S.status !== "found") fail(S.status === "blocked" ? "the " + S.blockedEnd + " cell is blocked" : "no path");
    return toCells(S.path, shape[1]);
  }

  root.rappLive = {
    version: "1",
    parseScenario: parseScenario,
    axis: axis,
    occupancy: occupancy,
    occupancyOf: occupancyOf,
    Search: Search,
    astar: astar,
    toCells: toCells,
  };
})(typeof window !== "undefined" ? window : globalThis);
