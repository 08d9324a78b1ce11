"""The inline script of the launch animation (runtime/simulate/animation.py): one function of the
container <div> and the data, drawing SVG each frame (no library, no fetch). Kept as Python text so
that the wheel carries it with the module."""
# ruff: noqa: E501  (the text below is JavaScript, not Python)
from __future__ import annotations

SCRIPT = r"""function(root, D) {
  var NS = "http://www.w3.org/2000/svg", svg = root.querySelector("svg");
  var btn = root.querySelector("button"), sel = root.querySelector("select");
  var slider = root.querySelector("input"), label = root.querySelector("span");
  (function () {           // the frames, packed as whole numbers (animation.py pack)
    var K = D.pack;
    function sc(a, q) { return a.map(function (v) { return v * q; }); }
    D.x = sc(K.x, K.q_xy); D.y = sc(K.y, K.q_xy);
    D.z = K.dz.map(function (v) { return (D.z_s || 0) + v * K.q_z; });
    var nx = sc(K.nx, K.q_n), ny = sc(K.ny, K.q_n);
    D.n = [nx, ny, K.nz ? sc(K.nz, K.q_n) : nx.map(function (v, i) { return Math.sqrt(Math.max(0, 1 - v * v - ny[i] * ny[i])); })];
    D.phi = K.phi;
  })();
  var N = D.t.length, T0 = D.t[0], T1 = D.t[N - 1], E = 0.35, ce = Math.cos(E), se = Math.sin(E);
  function el(tag, at, parent) {
    var e = document.createElementNS(NS, tag);
    for (var k in at) e.setAttribute(k, at[k]);
    (parent || svg).appendChild(e); return e;
  }
  function txt(x, y, s, at) {
    var e = el("text", Object.assign({x: x, y: y, fill: "#333"}, at || {})); e.textContent = s; return e;
  }
  function fmt(v) { var a = Math.abs(v); return a >= 1e4 || (a < 1e-3 && a > 0) ? v.toExponential(2) : String(+v.toPrecision(4)); }
  function len(v) {      // as runtime/ui/human.py Units.length: m, cm, mm or um (SI), a bare number otherwise
    if (!D.si) return fmt(v);
    var a = Math.abs(v), u = a >= 1 || a === 0 ? [1, "m"] : a >= 0.01 ? [100, "cm"] : a >= 1e-5 ? [1e3, "mm"] : a >= 1e-9 ? [1e6, "um"] : [1, "m"];
    return fmt(v * u[0]) + " " + u[1];
  }
  function nice(v) { var e = Math.pow(10, Math.floor(Math.log10(v))), m = v / e; return (m >= 5 ? 5 : m >= 2 ? 2 : 1) * e; }
  // ---- the scene, to scale: orthographic view from 20 degrees above the horizon
  var ext = D.top_r * 3, thick = 0;
  D.base.forEach(function (b) { ext = Math.max(ext, b.r_out || 0, b.half_x || 0, b.half_y || 0); thick = Math.max(thick, b.thickness || 0); });
  ext *= 1.12;
  var zmax = Math.max(D.z_s || 0, Math.max.apply(null, D.z)) + D.top_h + 2.5 * D.top_r;
  var zlo = Math.min(0, Math.min.apply(null, D.z));
  var k = Math.min(420 / (2 * ext), 400 / ((zmax - zlo) * ce + thick * ce + 2 * ext * se));
  var cx = 220, cy = 430 - (thick * ce + ext * se - zlo * ce) * k;
  function P(x, y, z) { return [cx + k * x, cy - k * (z * ce + y * se)]; }
  function pts(a) { return a.map(function (p) { return p[0].toFixed(1) + "," + p[1].toFixed(1); }).join(" "); }
  function ring(r, z) { var o = []; for (var i = 0; i < 48; i++) { var a = 2 * Math.PI * i / 48; o.push(P(r * Math.cos(a), r * Math.sin(a), z)); } return o; }
  var bg = el("g", {});
  D.base.forEach(function (b) {
    var t = b.thickness || 0;
    if (b.kind === "rect") {
      var X = b.half_x, Y = b.half_y, top = [P(-X, -Y, 0), P(X, -Y, 0), P(X, Y, 0), P(-X, Y, 0)];
      if (t > 0) el("polygon", {points: pts([P(-X, -Y, 0), P(X, -Y, 0), P(X, -Y, -t), P(-X, -Y, -t)]), fill: "#8a8f99"}, bg);
      el("polygon", {points: pts(top), fill: "#b9bec8", stroke: "#666"}, bg);
      if (b.r_in > 0) el("polygon", {points: pts(ring(b.r_in, 0)), fill: "#f4f4f4", stroke: "#666"}, bg);
      return;
    }
    if (b.kind === "loop") { el("polygon", {points: pts(ring(b.r_out, 0)), fill: "none", stroke: "#c77d1a", "stroke-width": 3}, bg); return; }
    if (t > 0) {
      var lo = P(-b.r_out, 0, -t), hi = P(b.r_out, 0, 0);
      el("polygon", {points: pts(ring(b.r_out, -t)), fill: "#8a8f99"}, bg);
      el("rect", {x: lo[0], y: hi[1], width: hi[0] - lo[0], height: lo[1] - hi[1], fill: "#8a8f99"}, bg);
    }
    el("polygon", {points: pts(ring(b.r_out, 0)), fill: "#b9bec8", stroke: "#666"}, bg);
    if (b.r_in > 0) el("polygon", {points: pts(ring(b.r_in, 0)), fill: "#f4f4f4", stroke: "#666"}, bg);
  });
  if (!D.base.length) txt(20, 420, "the field is given by a formula: no base to draw", {"font-size": 11});
  if (D.z_s) {
    var a = P(-ext, 0, D.z_s), b2 = P(ext, 0, D.z_s);
    el("line", {x1: a[0], y1: a[1], x2: b2[0], y2: b2[1], stroke: "#3a7", "stroke-dasharray": "4 4"});
  }
  var shadow = el("ellipse", {fill: "rgba(0,0,0,0.15)"});
  var body = el("polygon", {fill: "#c0392b", stroke: "#7b241c"});
  var face = el("polygon", {fill: "#e8705f", stroke: "#7b241c"});
  var spoke = el("line", {stroke: "#fff", "stroke-width": 2});
  var dot = el("circle", {r: 3.5, fill: "#fff", stroke: "#222"});
  var axis = el("line", {stroke: "#111", "stroke-width": 1.5});
  if (D.z_s) {         // over the top, with a white halo: the label stays readable where the top passes
    var zl = P(-ext, 0, D.z_s);
    txt(zl[0] + 2, zl[1] + 13, "hover height z_s = " + len(D.z_s),
        {"font-size": 11, fill: "#3a7", stroke: "#fff", "stroke-width": 3, "paint-order": "stroke"});
  }
  txt(10, 16, "the top over its base, to scale", {"font-weight": "bold"});
  // ---- the trace on the horizontal plane, magnified
  var TX = 570, TY = 118, TR = 95, rr = D.x.map(function (x, i) { return Math.hypot(x, D.y[i]); }).slice().sort(function (a, b) { return a - b; });
  var Rt = Math.max(rr[Math.floor(0.97 * (N - 1))], 1e-12) * 1.15, kt = TR / Rt;
  el("rect", {x: TX - TR - 5, y: TY - TR - 5, width: 2 * TR + 10, height: 2 * TR + 10, fill: "#fafafa", stroke: "#ccc"});
  el("line", {x1: TX - TR, y1: TY, x2: TX + TR, y2: TY, stroke: "#ddd"}); el("line", {x1: TX, y1: TY - TR, x2: TX, y2: TY + TR, stroke: "#ddd"});
  var bar = nice(Rt * 0.6);
  el("line", {x1: TX - TR + 4, y1: TY + TR - 4, x2: TX - TR + 4 + bar * kt, y2: TY + TR - 4, stroke: "#000", "stroke-width": 2});
  txt(TX - TR + 4, TY + TR - 9, len(bar), {"font-size": 10});
  txt(TX - TR - 5, TY - TR - 10, "trace of the centre from above (x" + fmt(kt / k) + ")", {"font-weight": "bold"});
  var trail = el("polyline", {fill: "none", stroke: "#2c6fb7", "stroke-width": 1.2});
  var now = el("circle", {r: 3.5, fill: "#c0392b"});
  var read = txt(690, 40, "", {"font-size": 13});
  // ---- spin and height against time
  function chart(y0, h, v, title, unit) {
    var lo = Math.min.apply(null, v), hi = Math.max.apply(null, v);
    if (title === "spin" && D.lower) { lo = Math.min(lo, D.lower); hi = Math.max(hi, Math.min(D.upper || hi, 1.02 * hi)); }
    if (title === "spin" && hi - lo < 1e-3 * Math.abs(hi)) { lo = 0.95 * lo; hi = 1.05 * hi; }   // a steady spin
    if (hi - lo < 1e-12 * Math.max(1, Math.abs(hi))) { hi += 1e-9 + Math.abs(hi) * 1e-6; lo -= 1e-9 + Math.abs(lo) * 1e-6; }
    var pad = 0.08 * (hi - lo); lo -= pad; hi += pad;
    var X0 = 500, W = 385, c = {X0: X0, W: W, y0: y0, h: h, lo: lo, hi: hi};
    c.x = function (t) { return X0 + W * (t - T0) / ((T1 - T0) || 1); };
    c.y = function (u) { return y0 + h - h * (u - lo) / (hi - lo); };
    el("rect", {x: X0, y: y0, width: W, height: h, fill: "#fafafa", stroke: "#ccc"});
    el("polyline", {points: pts(v.map(function (u, i) { return [c.x(D.t[i]), c.y(u)]; })), fill: "none", stroke: "#2c6fb7", "stroke-width": 1.3});
    txt(X0, y0 - 4, title + " (" + unit + ")", {"font-weight": "bold"});
    txt(X0 - 4, y0 + 10, fmt(hi), {"font-size": 10, "text-anchor": "end"}); txt(X0 - 4, y0 + h, fmt(lo), {"font-size": 10, "text-anchor": "end"});
    c.cur = el("line", {y1: y0, y2: y0 + h, stroke: "#c0392b"});
    return c;
  }
  var S = chart(240, 80, D.w, "spin", D.rate_unit);
  var Hh = chart(352, 62, D.z.map(function (z) { return z * D.k_len; }), "height above the base", D.len_unit || "scene units");
  txt(500, 432, fmt(T0), {"font-size": 10}); txt(885, 432, fmt(T1) + " " + D.time_unit, {"font-size": 10, "text-anchor": "end"});
  txt(692, 432, "time", {"font-size": 10, "text-anchor": "middle"});
  if (D.lower) {
    el("line", {x1: S.X0, x2: S.X0 + S.W, y1: S.y(D.lower), y2: S.y(D.lower), stroke: "#c0392b", "stroke-dasharray": "5 3"});
    txt(S.X0 + 4, S.y(D.lower) - 3, "lower limit " + fmt(D.lower) + " " + D.rate_unit, {"font-size": 10, fill: "#c0392b"});
  }
  if (D.t_lower !== null) {
    [S, Hh].forEach(function (c) { el("line", {x1: c.x(D.t_lower), x2: c.x(D.t_lower), y1: c.y0, y2: c.y0 + c.h, stroke: "#c0392b", "stroke-dasharray": "2 2"}); });
    txt(S.x(D.t_lower) - 3, S.y0 + 12, "spin crosses the lower limit, t = " + fmt(D.t_lower) + " " + D.time_unit, {"font-size": 10, "text-anchor": "end", fill: "#c0392b"});
  }
  if (D.t_fall !== null) txt(Hh.x(D.t_fall) - 3, Hh.y0 + Hh.h - 4, "falls, t = " + fmt(D.t_fall) + " " + D.time_unit, {"font-size": 10, "text-anchor": "end"});
  if (D.z_s) el("line", {x1: Hh.X0, x2: Hh.X0 + Hh.W, y1: Hh.y(D.z_s * D.k_len), y2: Hh.y(D.z_s * D.k_len), stroke: "#3a7", "stroke-dasharray": "4 4"});
  // ---- one frame
  function at(t) {
    var lo = 0, hi = N - 1;
    while (hi - lo > 1) { var m = (lo + hi) >> 1; if (D.t[m] <= t) lo = m; else hi = m; }
    var f = hi > lo ? Math.min(1, Math.max(0, (t - D.t[lo]) / (D.t[hi] - D.t[lo]))) : 0;
    function mix(a) { return a[lo] + f * (a[hi] - a[lo]); }
    return {i: lo, f: f, mix: mix};
  }
  function hull(p) {
    p = p.slice().sort(function (a, b) { return a[0] - b[0] || a[1] - b[1]; });
    function cr(o, a, b) { return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]); }
    var L = [], U = [];
    p.forEach(function (q) { while (L.length > 1 && cr(L[L.length - 2], L[L.length - 1], q) <= 0) L.pop(); L.push(q); });
    p.reverse().forEach(function (q) { while (U.length > 1 && cr(U[U.length - 2], U[U.length - 1], q) <= 0) U.pop(); U.push(q); });
    return L.slice(0, -1).concat(U.slice(0, -1));
  }
  function draw(t) {
    var s = at(t), x = s.mix(D.x), y = s.mix(D.y), z = s.mix(D.z);
    var n = [s.mix(D.n[0]), s.mix(D.n[1]), s.mix(D.n[2])], nn = Math.hypot(n[0], n[1], n[2]);
    n = n.map(function (v) { return v / nn; });
    var e1 = [1 - n[0] * n[0], -n[0] * n[1], -n[0] * n[2]], l1 = Math.hypot(e1[0], e1[1], e1[2]);
    e1 = e1.map(function (v) { return v / l1; });
    var e2 = [n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]];
    var ph = s.mix(D.phi), cp = Math.cos(ph), sp = Math.sin(ph);
    var m = [cp * e1[0] + sp * e2[0], cp * e1[1] + sp * e2[1], cp * e1[2] + sp * e2[2]];
    var r = D.top_r, hh = Math.max(D.top_h, 0.2 * r) / 2, vis = (-n[1] * se + n[2] * ce) >= 0 ? 1 : -1;
    function circ(sg) { var o = []; for (var i = 0; i < 36; i++) { var a = 2 * Math.PI * i / 36, c = Math.cos(a), sn = Math.sin(a);
      o.push(P(x + sg * hh * n[0] + r * (c * e1[0] + sn * e2[0]), y + sg * hh * n[1] + r * (c * e1[1] + sn * e2[1]), z + sg * hh * n[2] + r * (c * e1[2] + sn * e2[2]))); } return o; }
    var up = circ(vis), down = circ(-vis);
    body.setAttribute("points", pts(hull(up.concat(down)))); face.setAttribute("points", pts(up));
    var fc = P(x + vis * hh * n[0], y + vis * hh * n[1], z + vis * hh * n[2]);
    var mk = P(x + vis * hh * n[0] + r * m[0], y + vis * hh * n[1] + r * m[1], z + vis * hh * n[2] + r * m[2]);
    spoke.setAttribute("x1", fc[0]); spoke.setAttribute("y1", fc[1]); spoke.setAttribute("x2", mk[0]); spoke.setAttribute("y2", mk[1]);
    dot.setAttribute("cx", mk[0]); dot.setAttribute("cy", mk[1]);
    var L = hh + 1.8 * r, a0 = P(x - L * n[0], y - L * n[1], z - L * n[2]), a1 = P(x + L * n[0], y + L * n[1], z + L * n[2]);
    axis.setAttribute("x1", a0[0]); axis.setAttribute("y1", a0[1]); axis.setAttribute("x2", a1[0]); axis.setAttribute("y2", a1[1]);
    var sh = P(x, y, 0); shadow.setAttribute("cx", sh[0]); shadow.setAttribute("cy", sh[1]);
    shadow.setAttribute("rx", r * k); shadow.setAttribute("ry", r * k * se);
    var first = Math.max(0, s.i - 150), tr = [];
    for (var i = first; i <= s.i; i++) tr.push([TX + kt * D.x[i], TY - kt * D.y[i]]);
    tr.push([TX + kt * x, TY - kt * y]);
    trail.setAttribute("points", pts(tr)); now.setAttribute("cx", TX + kt * x); now.setAttribute("cy", TY - kt * y);
    [S, Hh].forEach(function (c) { var X = c.x(t); c.cur.setAttribute("x1", X); c.cur.setAttribute("x2", X); });
    var tilt = Math.acos(Math.max(-1, Math.min(1, n[2]))) * 180 / Math.PI;
    read.textContent = "";
    ["t = " + fmt(t) + " " + D.time_unit, "spin " + fmt(s.mix(D.w)) + " " + D.rate_unit, "height " + len(z),
     "off the axis " + len(Math.hypot(x, y)), "tilt " + fmt(tilt) + " deg"].forEach(function (line, j) {
      var ts = document.createElementNS(NS, "tspan"); ts.setAttribute("x", 690); ts.setAttribute("dy", j ? 18 : 0); ts.textContent = line; read.appendChild(ts); });
    slider.value = Math.round(1000 * (t - T0) / ((T1 - T0) || 1));
    label.textContent = "t = " + fmt(t) + " of " + fmt(T1) + " " + D.time_unit + (D.si ? " (x" + fmt(D.speed * +sel.value) + " real time)" : " (" + fmt(D.speed * +sel.value) + " " + D.time_unit + " a second)");
  }
  var playing = true, t = T0, last = performance.now(), hold = 0;
  function tick() {        // a timer, not requestAnimationFrame: it also runs in a headless browser's virtual time
    var ms = performance.now(), dt = (ms - last) / 1000; last = ms;
    if (!playing) return;
    if (t >= T1) { hold += dt; if (hold > 1.5) { t = T0; hold = 0; } }
    else t = Math.min(T1, t + dt * D.speed * +sel.value);
    draw(t);
  }
  btn.onclick = function () { playing = !playing; btn.textContent = playing ? "pause" : "play"; };
  slider.oninput = function () { t = T0 + (T1 - T0) * slider.value / 1000; draw(t); };
  draw(T0); setInterval(tick, 40);
}"""
