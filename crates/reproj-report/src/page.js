// The budget slider: reads the precomputed choices (#data), shows the one for the slider's budget,
// draws the speedup-vs-error chart, and marks <body data-images-ok> once every image has loaded.
// `#budget=X` in the address sets the slider and dispatches `input`, as a drag does.
(function () {
  "use strict";
  var D = JSON.parse(document.getElementById("data").textContent);
  var slider = document.getElementById("budget");
  var STEPS = +slider.max;
  var lo = D.range[0], hi = D.range[1];
  var budgetAt = function (v) { return lo * Math.pow(hi / lo, v / STEPS); };
  var valueOf = function (b) { return Math.round(STEPS * Math.log(b / lo) / Math.log(hi / lo)); };
  var $ = function (id) { return document.getElementById(id); };
  var SVG = "http://www.w3.org/2000/svg";
  var PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
    "#bcbd22", "#17becf", "#393b79", "#b8860b", "#637939"];

  // The entry with the largest budget <= b (the lowest one below the range), as budgets.rs does.
  function entryAt(b) {
    var a = 0, z = D.entries.length;
    while (a < z) { var m = (a + z) >> 1; if (D.entries[m].budget <= b) a = m + 1; else z = m; }
    return D.entries[Math.max(0, a - 1)];
  }
  function fmt(x, d) { return x === null || x === undefined || !isFinite(x) ? "–" : x.toFixed(d); }
  function metricText(m) { return fmt(m.value, m.decimals) + (m.unit ? " " + m.unit : ""); }

  // ---- chart: speedup (y) vs error (x, log)
  var W = 640, H = 420, L = 56, R = 16, T = 16, B = 44;
  var svg = $("chart");
  var pts = D.points.filter(function (p) { return p.error > 0 && isFinite(p.speedup); });
  var ymax = Math.max(1.2, Math.max.apply(null, pts.map(function (p) { return p.speedup; }).concat([1]))) * 1.08;
  var lx0 = Math.log10(lo), lx1 = Math.log10(hi);
  var X = function (e) { return L + (Math.log10(Math.max(e, lo)) - lx0) / (lx1 - lx0) * (W - L - R); };
  var Y = function (s) { return H - B - s / ymax * (H - T - B); };
  function el(name, attrs, text) {
    var e = document.createElementNS(SVG, name);
    for (var k in attrs) e.setAttribute(k, attrs[k]);
    if (text !== undefined) e.textContent = text;
    svg.appendChild(e);
    return e;
  }
  var nodes = [];
  pts.forEach(function (p) { if (nodes.indexOf(p.node) < 0) nodes.push(p.node); });
  nodes.sort(function (a, b) { return a - b; });
  var colorOf = function (n) { return PALETTE[nodes.indexOf(n) % PALETTE.length]; };
  for (var d = Math.floor(lx0); d <= Math.ceil(lx1); d++) {
    [1, 2, 5].forEach(function (m) {
      var v = m * Math.pow(10, d);
      if (v < lo || v > hi) return;
      var x = X(v);
      el("line", { x1: x, x2: x, y1: T, y2: H - B, stroke: m === 1 ? "#ddd" : "#f0f0f0" });
      el("text", { x: x, y: H - B + 16, "text-anchor": "middle" }, String(+v.toPrecision(1)));
    });
  }
  var ystep = ymax > 8 ? 2 : ymax > 4 ? 1 : 0.5;
  for (var s = 0; s <= ymax; s += ystep) {
    el("line", { x1: L, x2: W - R, y1: Y(s), y2: Y(s), stroke: "#eee" });
    el("text", { x: L - 6, y: Y(s) + 4, "text-anchor": "end" }, s + "×");
  }
  el("line", { x1: L, x2: W - R, y1: Y(1), y2: Y(1), stroke: "#202020", "stroke-dasharray": "8 5" });
  el("text", { x: W - R - 4, y: Y(1) - 5, "text-anchor": "end" }, "original (1×)");
  el("text", { x: (L + W - R) / 2, y: H - 8, "text-anchor": "middle" }, "error (mean per-pixel L2, log scale)");
  el("text", { x: 14, y: (T + H - B) / 2, transform: "rotate(-90 14 " + (T + H - B) / 2 + ")", "text-anchor": "middle" }, "speedup over the original");
  pts.forEach(function (p) {
    var c = colorOf(p.node);
    var dot = el("circle", p.measured
      ? { cx: X(p.error), cy: Y(p.speedup), r: 3.5, fill: c }
      : { cx: X(p.error), cy: Y(p.speedup), r: 2, fill: "none", stroke: c, "stroke-opacity": 0.55 });
    var t = document.createElementNS(SVG, "title");
    t.textContent = "node " + p.node + " (" + p.strategy + ") Δn = " + p.delta_n + ": error " +
      p.error.toPrecision(3) + ", " + p.speedup.toFixed(2) + "× (" + (p.measured ? "measured" : "predicted") + ")";
    dot.appendChild(t);
  });
  nodes.forEach(function (n, i) {
    el("circle", { cx: L + 14, cy: T + 10 + i * 15, r: 4, fill: colorOf(n) });
    el("text", { x: L + 22, y: T + 14 + i * 15 }, "node " + n);
  });
  el("text", { x: L + 14, y: T + 14 + nodes.length * 15 + 4, fill: "#606060" }, "filled: measured · rings: predicted");
  var budgetLine = el("line", { y1: T, y2: H - B, stroke: "#b03020", "stroke-width": 2 });
  var ring = el("circle", { r: 9, fill: "none", stroke: "#000", "stroke-width": 2.5 });

  // ---- selection
  var groups = document.querySelectorAll(".choice-frames");
  function show() {
    var b = budgetAt(+slider.value);
    $("budget-value").textContent = "ε ≤ " + b.toPrecision(3);
    var e = entryAt(b);
    // The selection's frames, or those of the nearest selection that has frames (over the
    // `--max-rendered` limit a selection has none; choices are numbered by increasing budget).
    var key = "original", note = "";
    if (e.choice !== null) {
      var best = null;
      for (var g = 0; g < groups.length; g++) {
        var k = groups[g].getAttribute("data-choice");
        if (k === "original") continue;
        if (best === null || Math.abs(+k - e.choice) < Math.abs(+best - e.choice)) best = k;
      }
      key = best === null ? "" : best;
      if (best !== null && +best !== e.choice) {
        var label = document.querySelector('.choice-frames[data-choice="' + best + '"]').getAttribute("data-label");
        note = "Frames of the nearest rendered selection, " + label + " (this one is over the --max-rendered limit).";
      }
    }
    $("frames-note").textContent = note;
    for (var i = 0; i < groups.length; i++) groups[i].hidden = groups[i].getAttribute("data-choice") !== key;
    budgetLine.setAttribute("x1", X(b)); budgetLine.setAttribute("x2", X(b));
    var rows = [];
    if (e.choice === null) {
      $("sel-node").textContent = "original shader";
      $("sel-strategy").textContent = ""; $("sel-dn").textContent = "";
      $("sel-text").textContent = ""; $("sel-source").textContent = "";
      $("sel-reason").textContent = e.reason || "";
      ring.setAttribute("visibility", "hidden");
    } else {
      var c = D.choices[e.choice];
      $("sel-node").textContent = c.label + (c.root ? " (root)" : "");
      $("sel-strategy").textContent = c.reconstruct && c.reconstruct !== "bilinear"
        ? c.strategy + " · " + c.reconstruct : c.strategy;
      $("sel-dn").textContent = "Δn = " + c.delta_n;
      $("sel-text").textContent = c.text;
      var caret = c.col > 0 ? "\n" + " ".repeat(String(c.line).length + 2 + c.col - 1) + "^" : "";
      $("sel-source").textContent = c.line > 0 ? c.line + ": " + c.source + caret : "";
      $("sel-reason").textContent = "";
      var ci = function (v) { return v ? " [" + fmt(v[0], 2) + ", " + fmt(v[1], 2) + "]" : ""; };
      rows.push(["predicted", "error " + fmt(c.predicted_error, 5) + " · " + fmt(c.predicted_ms, 3) + " ms · " + fmt(c.predicted_speedup, 2) + "×" + ci(c.predicted_speedup_ci95)]);
      var r = c.measured;
      if (r) rows.push(["measured now", r.metrics.map(function (m) { return m.name + " " + metricText(m); }).join(" · ") +
        " · " + fmt(r.frame_ms, 3) + " ms vs " + fmt(r.original_ms, 3) + " ms · " + fmt(r.speedup, 2) + "×" + ci(r.speedup_ci95) + " (interleaved)"]);
      if (c.profiled) rows.push(["profiled", c.profiled.map(function (m) { return m.name + " " + metricText(m); }).join(" · ")]);
      ring.setAttribute("visibility", "visible");
      ring.setAttribute("cx", X(c.predicted_error)); ring.setAttribute("cy", Y(c.predicted_speedup));
    }
    var t = $("sel-numbers");
    t.textContent = "";
    rows.forEach(function (r) {
      var tr = t.insertRow(), th = document.createElement("th");
      th.textContent = r[0]; tr.appendChild(th); tr.insertCell().textContent = r[1];
    });
  }
  slider.addEventListener("input", show);
  function fromHash() {
    var m = /budget=([0-9.eE+-]+)/.exec(location.hash);
    var b = m ? parseFloat(m[1]) : NaN;
    if (!(b > 0)) return false;
    slider.value = String(Math.min(STEPS, Math.max(0, valueOf(b))));
    slider.dispatchEvent(new Event("input", { bubbles: true }));
    return true;
  }
  window.addEventListener("hashchange", fromHash);
  if (!fromHash()) {
    slider.value = String(Math.min(STEPS, Math.max(0, valueOf(+document.body.getAttribute("data-start-budget")))));
    show();
  }

  // ---- every image loaded?
  function checkImages() {
    var imgs = Array.prototype.slice.call(document.images);
    var ok = imgs.every(function (i) { return i.complete && i.naturalWidth > 0; });
    document.body.setAttribute("data-images", String(imgs.length));
    document.body.setAttribute("data-images-ok", ok ? "true" : "false");
  }
  if (document.readyState === "complete") checkImages(); else window.addEventListener("load", checkImages);
})();
