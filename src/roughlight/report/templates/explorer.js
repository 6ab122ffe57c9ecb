/* roughlight's hemisphere explorer: every measured view of the study's surfaces, drawn in the report page.
 *
 * The data (rule explorer_data, roughlight.report.explorer) sit in two blocks that do not run: an index
 * (#explorer-index, JSON) and the sweeps (#explorer-data, base64 of one zlib stream of them all). A sweep is
 * 3 components x n_azimuths x n_elevations values in hundredths of a level; total is stored as
 * total - diffuse - specular, each half great circle as differences along elevation (mod 2^16), the 16-bit
 * numbers as a low and a high byte plane. Maps colour each pixel by the measured view nearest to it on the
 * sphere: nothing is interpolated, mirrored or invented.
 *
 * Views: direction (cos e cos phi, cos e sin phi, sin e), azimuth phi in [0, 180), elevation e in [0, 180];
 * top-down maps put x (toward the light) to the right and y up.
 *
 * window.roughlight.explorer.ready: a Promise resolved once the data are decoded.
 * window.roughlight.explorer.value({kind, seed, truncation, aspect, incidence, component, azimuth, elevation}):
 *   that view's value to 0.01 of a level, or null for a view the page does not hold. kind: a value of the study
 *   table's kind, or "control" (the plate; truncation and aspect ignored); seed: null for a random kind's
 *   ensemble mean (and for the regular surface), or a seed number the page holds.
 */
(function () {
  "use strict";
  var MISSING = -32768;
  var KIND_NAMES = {pyramids: "regular pyramids", random_pyramids: "random pyramids",
                    random_heightfield: "random heightfield", control: "control plate"};
  var MAGMA = ["#000004", "#1c1044", "#4f127b", "#812581", "#b5367a", "#e55064", "#fb8761", "#fec287", "#fcfdbf"];
  var RDBU = ["#053061", "#2166ac", "#4393c3", "#92c5de", "#f7f7f7", "#f4a582", "#d6604d", "#b2182b", "#67001f"];
  var MAP = {width: 330, height: 372, cx: 165, cy: 160, radius: 150};
  var CURVE = {width: 420, height: 372, left: 44, right: 12, top: 14, bottom: 40};

  var root = window.roughlight = window.roughlight || {};
  var settle = {};
  var api = root.explorer = {
    ready: new Promise(function (resolve, reject) { settle.resolve = resolve; settle.reject = reject; }),
    value: value,
    startedAt: performance.now(),
    readyAt: null
  };
  api.ready.catch(function () { /* shown in the page's status line */ });

  var index = JSON.parse(document.getElementById("explorer-index").textContent);
  var AZ = index.azimuths, EL = index.elevations, NAZ = AZ.length, NEL = EL.length, PER = NAZ * NEL;
  var COMPONENTS = index.components;

  function $(id) { return document.getElementById(id); }
  function same(a, b) { return a !== null && b !== null && a !== undefined && b !== undefined &&
                               Math.abs(Number(a) - Number(b)) <= 1e-9 * Math.max(1, Math.abs(Number(a))); }
  function position(list, x) {
    for (var i = 0; i < list.length; i++) { if (same(list[i], x)) { return i; } }
    return -1;
  }
  function rad(d) { return d * Math.PI / 180; }
  function fixed(x, n) { return (Math.round(x * 100) / 100).toFixed(n === undefined ? 2 : n); }
  function label(x) { return String(Math.round(Number(x) * 1e6) / 1e6); }
  function aspectLabel(a) {
    for (var i = 0; i < index.aspect_labels.length; i++) {
      if (same(index.aspect_labels[i][0], a)) { return index.aspect_labels[i][1]; }
    }
    return label(a);
  }

  // ------------------------------------------------------------------ the data

  function base64Bytes(text) {
    var binary = atob(text.replace(/\s+/g, "")), out = new Uint8Array(binary.length);
    for (var i = 0; i < binary.length; i++) { out[i] = binary.charCodeAt(i); }
    return out;
  }

  function inflate(bytes) {
    var stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
    return new Response(stream).arrayBuffer().then(function (buffer) { return new Uint8Array(buffer); });
  }

  function decodeSweep(raw, missing) {
    var n = 3 * PER, out = new Int16Array(n), row, j, i, acc;
    if (raw.length !== 2 * n) { throw new Error("a sweep of " + raw.length + " bytes, expected " + 2 * n); }
    for (row = 0; row < 3 * NAZ; row++) {
      acc = 0;
      for (j = 0; j < NEL; j++) {
        i = row * NEL + j;
        acc = (acc + (raw[i] | (raw[n + i] << 8))) & 0xFFFF;
        out[i] = (acc << 16) >> 16;
      }
    }
    for (i = 0; i < PER; i++) { out[2 * PER + i] += out[i] + out[PER + i]; }
    if (missing) {
      var flags = base64Bytes(missing);
      for (i = 0; i < n; i++) { if (flags[i >> 3] & (128 >> (i & 7))) { out[i] = MISSING; } }
    }
    return out;
  }

  function find(kind, seed, truncation, aspect, incidence) {
    var sets = index.datasets, d, i;
    var wantSeed = (seed === undefined || seed === null || (kind === "pyramids" && Number(seed) === 0)) ? null
      : Number(seed);
    for (i = 0; i < sets.length; i++) {
      d = sets[i];
      if (d.kind !== kind || !same(d.incidence, incidence)) { continue; }
      if (kind === "control") { return d; }
      if (same(d.truncation, truncation) && same(d.aspect, aspect) &&
          (d.seed === null ? wantSeed === null : wantSeed !== null && d.seed === wantSeed)) { return d; }
    }
    return null;
  }

  function value(q) {
    q = q || {};
    var d = find(q.kind, q.seed, q.truncation, q.aspect, q.incidence);
    var c = COMPONENTS.indexOf(q.component), k = position(AZ, q.azimuth), j = position(EL, q.elevation);
    if (!d || !d.values || c < 0 || k < 0 || j < 0) { return null; }
    var v = d.values[c * PER + k * NEL + j];
    return v === MISSING ? null : v / 100;
  }

  // ------------------------------------------------------------------ geometry: pixels to views

  var COS_AZ = new Float64Array(AZ.map(function (a) { return Math.cos(rad(a)); }));
  var SIN_AZ = new Float64Array(AZ.map(function (a) { return Math.sin(rad(a)); }));
  var COS_EL = new Float64Array(EL.map(function (e) { return Math.cos(rad(e)); }));
  var SIN_EL = new Float64Array(EL.map(function (e) { return Math.sin(rad(e)); }));
  var EL_STEP = NEL > 1 ? (EL[NEL - 1] - EL[0]) / (NEL - 1) : 0;
  var EL_UNIFORM = NEL > 1 && EL.every(function (e, j) { return Math.abs(e - (EL[0] + j * EL_STEP)) < 1e-6; });

  // the index of the grid elevation nearest to e (degrees)
  function nearestElevation(e) {
    if (EL_UNIFORM) { return Math.max(0, Math.min(NEL - 1, Math.round((e - EL[0]) / EL_STEP))); }
    var lo = 0, hi = NEL - 1, mid;
    while (hi - lo > 1) { mid = (lo + hi) >> 1; if (EL[mid] <= e) { lo = mid; } else { hi = mid; } }
    return Math.abs(EL[lo] - e) <= Math.abs(EL[hi] - e) ? lo : hi;
  }

  // the measured view nearest on the sphere to the top-down point (x, y) of the unit disc: k * NEL + j, or -1.
  // A view (k, j) has d . v = cos e_j (d . u_k) + sin e_j d_z, u_k its azimuth's unit vector: at an elevation
  // below 90 the best half great circle is the one of largest d . u_k, above 90 the one of smallest (at 90
  // every one is alike), so only those two circles hold the nearest view. On a circle the nearest point to d
  // lies at elevation atan2(d_z, d . u_k), and its nearest view at the grid elevation nearest to that.
  function viewAt(x, y) {
    var r2 = x * x + y * y;
    if (r2 > 1) { return -1; }
    var z = Math.sqrt(1 - r2), high = 0, low = 0, uHigh = -2, uLow = 2, k, u;
    for (k = 0; k < NAZ; k++) {
      u = x * COS_AZ[k] + y * SIN_AZ[k];
      if (u > uHigh) { uHigh = u; high = k; }
      if (u < uLow) { uLow = u; low = k; }
    }
    var jHigh = nearestElevation(Math.atan2(z, uHigh) * 180 / Math.PI);
    var jLow = nearestElevation(Math.atan2(z, uLow) * 180 / Math.PI);
    return COS_EL[jHigh] * uHigh + SIN_EL[jHigh] * z >= COS_EL[jLow] * uLow + SIN_EL[jLow] * z
      ? high * NEL + jHigh : low * NEL + jLow;
  }

  var pixelViews = null;
  function pixelMap() {
    if (pixelViews) { return pixelViews; }
    pixelViews = new Int32Array(MAP.width * MAP.height).fill(-1);
    for (var py = MAP.cy - MAP.radius; py <= MAP.cy + MAP.radius; py++) {
      for (var px = MAP.cx - MAP.radius; px <= MAP.cx + MAP.radius; px++) {
        pixelViews[py * MAP.width + px] = viewAt((px + 0.5 - MAP.cx) / MAP.radius, (MAP.cy - py - 0.5) / MAP.radius);
      }
    }
    return pixelViews;
  }

  function topdown(azimuth, elevation) {
    return [Math.cos(rad(elevation)) * Math.cos(rad(azimuth)), Math.cos(rad(elevation)) * Math.sin(rad(azimuth))];
  }

  // ------------------------------------------------------------------ colours

  function ramp(stops) {
    var rgb = stops.map(function (h) { return [1, 3, 5].map(function (i) { return parseInt(h.substr(i, 2), 16); }); });
    var lut = new Uint8Array(256 * 3);
    for (var i = 0; i < 256; i++) {
      var t = i / 255 * (rgb.length - 1), a = Math.min(Math.floor(t), rgb.length - 2), f = t - a;
      for (var c = 0; c < 3; c++) { lut[3 * i + c] = Math.round(rgb[a][c] * (1 - f) + rgb[a + 1][c] * f); }
    }
    return lut;
  }
  var LUTS = {magma: ramp(MAGMA), rdbu: ramp(RDBU)};

  function colourAt(lut, t) {
    var i = 3 * Math.max(0, Math.min(255, Math.round(t * 255)));
    return "rgb(" + lut[i] + "," + lut[i + 1] + "," + lut[i + 2] + ")";
  }

  // ------------------------------------------------------------------ drawing

  function context(canvas, width, height) {
    var ratio = window.devicePixelRatio || 1;
    if (canvas.width !== Math.round(width * ratio)) {
      canvas.width = Math.round(width * ratio);
      canvas.height = Math.round(height * ratio);
      canvas.style.width = width + "px";
      canvas.style.height = height + "px";
    }
    var ctx = canvas.getContext("2d");
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    ctx.clearRect(0, 0, width, height);
    return ctx;
  }

  // a map of per-view numbers (hundredths; MISSING: grey) on [lo, hi], with the light, the mirror direction and
  // the curve's azimuth marked, and a colour bar
  function drawMap(canvas, views, lo, hi, lut, incidence, azimuth, unit) {
    canvas.setAttribute("data-cx", MAP.cx);
    canvas.setAttribute("data-cy", MAP.cy);
    canvas.setAttribute("data-radius", MAP.radius);
    var ctx = context(canvas, MAP.width, MAP.height);
    var image = ctx.createImageData(MAP.width, MAP.height), pix = pixelMap(), span = Math.max(hi - lo, 1e-9);
    for (var p = 0; p < pix.length; p++) {
      var k = pix[p];
      if (k < 0) { continue; }
      var v = views[k], o = 4 * p;
      if (v === MISSING) {
        image.data[o] = image.data[o + 1] = image.data[o + 2] = 200;
      } else {
        var i = 3 * Math.max(0, Math.min(255, Math.round((v / 100 - lo) / span * 255)));
        image.data[o] = lut[i]; image.data[o + 1] = lut[i + 1]; image.data[o + 2] = lut[i + 2];
      }
      image.data[o + 3] = 255;
    }
    var scratch = document.createElement("canvas");
    scratch.width = MAP.width; scratch.height = MAP.height;
    scratch.getContext("2d").putImageData(image, 0, 0);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(scratch, 0, 0, MAP.width, MAP.height);
    // horizon, the curve's half great circle, the light and its mirror direction
    ctx.strokeStyle = "#888"; ctx.lineWidth = 1;
    ctx.beginPath(); ctx.arc(MAP.cx, MAP.cy, MAP.radius, 0, 2 * Math.PI); ctx.stroke();
    var a = topdown(azimuth, 0);
    ctx.setLineDash([4, 3]); ctx.strokeStyle = "rgba(255,255,255,0.8)";
    ctx.beginPath();
    ctx.moveTo(MAP.cx + a[0] * MAP.radius, MAP.cy - a[1] * MAP.radius);
    ctx.lineTo(MAP.cx - a[0] * MAP.radius, MAP.cy + a[1] * MAP.radius);
    ctx.stroke(); ctx.setLineDash([]);
    var c = Math.cos(rad(incidence));
    marker(ctx, MAP.cx + c * MAP.radius, MAP.cy, "star");
    marker(ctx, MAP.cx - c * MAP.radius, MAP.cy, "ring");
    colourBar(ctx, lo, hi, lut, unit);
  }

  function marker(ctx, x, y, shape) {
    ctx.lineWidth = 1.5;
    if (shape === "star") {
      ctx.beginPath();
      for (var i = 0; i < 10; i++) {
        var r = i % 2 ? 3.5 : 8, t = -Math.PI / 2 + i * Math.PI / 5;
        ctx.lineTo(x + r * Math.cos(t), y + r * Math.sin(t));
      }
      ctx.closePath(); ctx.fillStyle = "gold"; ctx.fill(); ctx.strokeStyle = "#000"; ctx.stroke();
    } else {
      ctx.beginPath(); ctx.arc(x, y, 7, 0, 2 * Math.PI); ctx.strokeStyle = "#0bf"; ctx.lineWidth = 2.5; ctx.stroke();
      ctx.beginPath(); ctx.arc(x, y, 7, 0, 2 * Math.PI); ctx.strokeStyle = "#000"; ctx.lineWidth = 0.8; ctx.stroke();
    }
  }

  function colourBar(ctx, lo, hi, lut, unit) {
    var x0 = 15, x1 = MAP.width - 15, y = MAP.cy + MAP.radius + 16, h = 11;
    for (var x = x0; x < x1; x++) { ctx.fillStyle = colourAt(lut, (x - x0) / (x1 - x0 - 1)); ctx.fillRect(x, y, 1, h); }
    ctx.strokeStyle = "#666"; ctx.lineWidth = 0.5; ctx.strokeRect(x0, y, x1 - x0, h);
    ctx.fillStyle = "#222"; ctx.font = "11px sans-serif"; ctx.textBaseline = "top";
    ctx.textAlign = "left"; ctx.fillText(fixed(lo), x0, y + h + 3);
    ctx.textAlign = "center"; ctx.fillText(unit, (x0 + x1) / 2, y + h + 3);
    ctx.textAlign = "right"; ctx.fillText(fixed(hi), x1, y + h + 3);
  }

  function niceStep(span) {
    var raw = span / 5, p = Math.pow(10, Math.floor(Math.log10(raw))), m = raw / p;
    return (m <= 1 ? 1 : m <= 2 ? 2 : m <= 5 ? 5 : 10) * p;
  }

  // the elevation curve at one azimuth: [values (levels or null), colour, dashed, label] a line
  function drawCurve(canvas, lines, azimuth, marked) {
    var ctx = context(canvas, CURVE.width, CURVE.height), c = CURVE;
    var w = c.width - c.left - c.right, h = c.height - c.top - c.bottom;
    var lo = 0, hi = 1;
    lines.forEach(function (line) {
      line[0].forEach(function (v) { if (v !== null) { lo = Math.min(lo, v); hi = Math.max(hi, v); } });
    });
    var step = niceStep(hi - lo);
    lo = Math.floor(lo / step) * step; hi = Math.ceil(hi / step) * step;
    function X(e) { return c.left + e / 180 * w; }
    function Y(v) { return c.top + (hi - v) / (hi - lo) * h; }
    ctx.font = "11px sans-serif"; ctx.fillStyle = "#222"; ctx.strokeStyle = "#ddd"; ctx.lineWidth = 1;
    ctx.textAlign = "right"; ctx.textBaseline = "middle";
    for (var v = lo; v <= hi + step / 2; v += step) {
      ctx.beginPath(); ctx.moveTo(c.left, Y(v)); ctx.lineTo(c.left + w, Y(v)); ctx.stroke();
      ctx.fillText(label(v), c.left - 4, Y(v));
    }
    ctx.textAlign = "center"; ctx.textBaseline = "top";
    for (var e = 0; e <= 180; e += 30) {
      ctx.beginPath(); ctx.moveTo(X(e), c.top); ctx.lineTo(X(e), c.top + h); ctx.stroke();
      ctx.fillText(String(e), X(e), c.top + h + 4);
    }
    ctx.fillText("elevation (deg) at azimuth " + label(azimuth), c.left + w / 2, c.top + h + 20);
    ctx.strokeStyle = "#999"; ctx.strokeRect(c.left, c.top, w, h);
    lines.forEach(function (line) {
      ctx.strokeStyle = line[1]; ctx.lineWidth = 1.6; ctx.setLineDash(line[2] ? [5, 3] : []);
      ctx.beginPath();
      var pen = false;
      line[0].forEach(function (v, j) {
        if (v === null) { pen = false; return; }
        if (pen) { ctx.lineTo(X(EL[j]), Y(v)); } else { ctx.moveTo(X(EL[j]), Y(v)); pen = true; }
      });
      ctx.stroke();
    });
    ctx.setLineDash([]);
    if (marked) {
      ctx.fillStyle = "#d00";
      ctx.beginPath(); ctx.arc(X(marked[0]), Y(marked[1]), 3.5, 0, 2 * Math.PI); ctx.fill();
    }
  }

  // ------------------------------------------------------------------ the controls

  function options(select, items, keep) {
    var previous = keep !== undefined ? keep : select.value;
    select.textContent = "";
    items.forEach(function (item) {
      var o = document.createElement("option");
      o.value = item[0]; o.textContent = item[1];
      select.appendChild(o);
    });
    var match = items.filter(function (item) { return item[0] === previous; });
    select.value = match.length ? previous : (items.length ? items[0][0] : "");
    select.disabled = items.length <= 1;
  }

  function unique(list) {
    var out = [];
    list.forEach(function (x) { if (position(out, x) < 0) { out.push(x); } });
    return out.sort(function (a, b) { return a - b; });
  }

  // a surface picker over five selects: kind, then truncation, aspect, incidence, then the seeds held there
  function Picker(prefix, onChange) {
    this.el = {};
    ["kind", "truncation", "aspect", "incidence", "seed"].forEach(function (name) {
      this.el[name] = $(prefix + "-" + name);
      this.el[name].addEventListener("change", function () { this.refresh(); onChange(); }.bind(this));
    }, this);
    var kinds = [];
    index.datasets.forEach(function (d) { if (d.kind !== "control" && kinds.indexOf(d.kind) < 0) { kinds.push(d.kind); } });
    kinds.sort(function (a, b) { return (a === "pyramids" ? "" : a) < (b === "pyramids" ? "" : b) ? -1 : 1; });
    options(this.el.kind, kinds.map(function (k) { return [k, KIND_NAMES[k] || k]; }));
  }

  Picker.prototype.refresh = function () {
    var el = this.el, kind = el.kind.value;
    var sets = index.datasets.filter(function (d) { return d.kind === kind; });
    options(el.truncation, unique(sets.map(function (d) { return d.truncation; })).map(function (t) {
      return [String(t), label(t)]; }));
    sets = sets.filter(function (d) { return same(d.truncation, el.truncation.value); });
    options(el.aspect, unique(sets.map(function (d) { return d.aspect; })).map(function (a) {
      return [String(a), aspectLabel(a)]; }));
    sets = sets.filter(function (d) { return same(d.aspect, el.aspect.value); });
    options(el.incidence, unique(sets.map(function (d) { return d.incidence; })).map(function (i) {
      return [String(i), label(i)]; }));
    sets = sets.filter(function (d) { return same(d.incidence, el.incidence.value); });
    var seeds = sets.map(function (d) {
      if (d.seed === null) { return ["", kind === "pyramids" ? "–" : "ensemble mean (" + d.seeds + " seeds)"]; }
      return [String(d.seed), "seed " + d.seed];
    });
    seeds.sort(function (a, b) { return (a[0] === "" ? -1 : Number(a[0])) - (b[0] === "" ? -1 : Number(b[0])); });
    options(el.seed, seeds);
  };

  Picker.prototype.choose = function (wanted) {
    var el = this.el;
    ["kind", "truncation", "aspect", "incidence", "seed"].forEach(function (name) {
      if (wanted[name] !== undefined) {
        var match = Array.prototype.filter.call(el[name].options, function (o) {
          return name === "kind" || name === "seed" ? o.value === String(wanted[name] === null ? "" : wanted[name])
            : same(o.value, wanted[name]);
        });
        if (match.length) { el[name].value = match[0].value; }
      }
      this.refresh();
    }, this);
  };

  Picker.prototype.dataset = function () {
    var el = this.el;
    return find(el.kind.value, el.seed.value === "" ? null : Number(el.seed.value), Number(el.truncation.value),
                Number(el.aspect.value), Number(el.incidence.value));
  };

  Picker.prototype.describe = function () {
    var d = this.dataset();
    if (!d) { return "no surface"; }
    var seed = d.kind === "pyramids" ? "" : d.seed === null ? ", ensemble mean" : ", seed " + d.seed;
    return (KIND_NAMES[d.kind] || d.kind) + seed + ", t " + label(d.truncation) + ", a " + aspectLabel(d.aspect) +
      ", i " + label(d.incidence);
  };

  // ------------------------------------------------------------------ the explorer

  var state = {};

  function componentViews(d, component) {
    var c = COMPONENTS.indexOf(component);
    return d && d.values ? d.values.subarray(c * PER, (c + 1) * PER) : null;
  }

  function comparison() {
    var mode = $("ex-compare").value, first = state.first.dataset();
    if (mode === "control") { return first ? find("control", null, null, null, first.incidence) : null; }
    if (mode === "surface") { return state.second.dataset(); }
    return null;
  }

  function comparisonName() {
    var mode = $("ex-compare").value, first = state.first.dataset();
    if (mode === "control") { return first ? "control plate, i " + label(first.incidence) : "control plate"; }
    return mode === "surface" ? state.second.describe() : "";
  }

  function draw() {
    var first = state.first.dataset(), other = comparison(), component = $("ex-component").value;
    var azimuth = AZ[Number($("ex-azimuth").value)];
    $("ex-second").hidden = $("ex-compare").value !== "surface";
    var views = componentViews(first, component);
    if (!views) { $("ex-status").textContent = "This surface is not held in the page."; return; }
    var hi = 1;
    for (var i = 0; i < PER; i++) { if (views[i] !== MISSING) { hi = Math.max(hi, views[i] / 100); } }
    drawMap($("ex-map"), views, 0, hi, LUTS.magma, first.incidence, azimuth, component + " (0–255)");
    $("ex-map-caption").textContent = state.first.describe() + ": " + component + ", every measured view";
    var otherViews = componentViews(other, component), diffPanel = $("ex-diff").parentNode;
    diffPanel.hidden = !otherViews;
    if (otherViews) {
      var diff = new Int16Array(PER), largest = 0;
      for (i = 0; i < PER; i++) {
        diff[i] = views[i] === MISSING || otherViews[i] === MISSING ? MISSING : views[i] - otherViews[i];
        if (diff[i] !== MISSING) { largest = Math.max(largest, Math.abs(diff[i]) / 100); }
      }
      var span = Math.max(largest, 0.05);
      drawMap($("ex-diff"), diff, -span, span, LUTS.rdbu, first.incidence, azimuth, "difference (levels)");
      $("ex-diff").setAttribute("data-largest", fixed(largest));
      $("ex-diff-caption").textContent = "minus " + comparisonName() + " (largest |difference| " + fixed(largest) +
        ")";
    }
    var k = Number($("ex-azimuth").value), lines = [];
    function curve(v) {
      var out = [];
      for (var j = 0; j < NEL; j++) { var x = v[k * NEL + j]; out.push(x === MISSING ? null : x / 100); }
      return out;
    }
    lines.push([curve(views), "#222", false]);
    if (otherViews) { lines.push([curve(otherViews), "#e07000", true]); }
    drawCurve($("ex-curve"), lines, azimuth, state.marked);
    $("ex-curve-caption").textContent = "solid: " + state.first.describe() +
      (otherViews ? "; dashed: " + comparisonName() : "") + " (" + component + ")";
    $("ex-status").textContent = "";
    $("ex-status").hidden = true;
  }

  function readout(event) {
    var canvas = event.currentTarget, rect = canvas.getBoundingClientRect();
    var x = (event.clientX - rect.left - MAP.cx) / MAP.radius, y = (MAP.cy - (event.clientY - rect.top)) / MAP.radius;
    var view = viewAt(x, y), out = $("ex-readout");
    if (view < 0) { out.textContent = "Outside the hemisphere."; out.removeAttribute("data-azimuth"); return; }
    var k = Math.floor(view / NEL), j = view % NEL, component = $("ex-component").value;
    var first = state.first.dataset(), other = comparison();
    var v = componentViews(first, component)[view];
    var text = "azimuth " + label(AZ[k]) + "°, elevation " + label(EL[j]) + "°: " +
      (v === MISSING ? "not measured" : fixed(v / 100));
    out.setAttribute("data-azimuth", AZ[k]);
    out.setAttribute("data-elevation", EL[j]);
    out.setAttribute("data-value", v === MISSING ? "" : fixed(v / 100));
    var w = other ? componentViews(other, component)[view] : null;
    if (other) {
      text += " · " + comparisonName() + " " + (w === MISSING ? "not measured" : fixed(w / 100));
      if (v !== MISSING && w !== MISSING) { text += " · difference " + fixed((v - w) / 100); }
      out.setAttribute("data-compare", w === MISSING ? "" : fixed(w / 100));
    } else {
      out.removeAttribute("data-compare");
    }
    out.textContent = text;
    if (k === Number($("ex-azimuth").value) && v !== MISSING) {
      state.marked = [EL[j], v / 100];
    } else {
      state.marked = null;
    }
    draw();
  }

  function start() {
    options($("ex-component"), COMPONENTS.map(function (c) { return [c, c]; }), "specular");
    options($("ex-azimuth"), AZ.map(function (a, k) { return [String(k), label(a) + "°"]; }), "0");
    state.first = new Picker("ex1", draw);
    state.second = new Picker("ex2", draw);
    var regular = index.datasets.filter(function (d) { return d.kind === "pyramids"; });
    var ts = unique(regular.map(function (d) { return d.truncation; }));
    var as = unique(regular.map(function (d) { return d.aspect; }));
    var is = unique(index.datasets.map(function (d) { return d.incidence; }));
    function nearest(list, x) {
      return list.reduce(function (b, v) { return Math.abs(v - x) < Math.abs(b - x) ? v : b; }, list[0]);
    }
    var initial = {kind: "pyramids", truncation: nearest(ts, 1), aspect: nearest(as, 1), incidence: nearest(is, 30)};
    state.first.choose(initial);
    state.second.choose({kind: "pyramids", truncation: nearest(ts, 0.5), aspect: nearest(as, 1),
                         incidence: initial.incidence});
    ["ex-component", "ex-azimuth", "ex-compare"].forEach(function (id) {
      $(id).addEventListener("change", function () { state.marked = null; draw(); });
    });
    ["ex-map", "ex-diff"].forEach(function (id) { $(id).addEventListener("mousemove", readout); });
    draw();
  }

  function fail(error) {
    $("ex-status").hidden = false;
    $("ex-status").textContent = "The explorer could not start: " + error.message;
    settle.reject(error);
  }

  try {
    if (!index.encoding || index.encoding.indexOf("roughlight-explorer/1") !== 0) {
      throw new Error("unknown data encoding " + index.encoding);
    }
    if (typeof DecompressionStream === "undefined") {
      throw new Error("this browser has no DecompressionStream (Chrome 80, Firefox 113, Safari 16.4 or newer)");
    }
    var text = $("explorer-data").textContent;
    (text.trim() ? inflate(base64Bytes(text)) : Promise.resolve(new Uint8Array(0))).then(function (planes) {
      index.datasets.forEach(function (d) { d.values = decodeSweep(planes.subarray(d.offset, d.offset + d.length),
                                                                   d.missing); });
    }).then(function () {
      start();
      api.readyAt = performance.now();
      settle.resolve(true);
    }).catch(fail);
  } catch (error) {
    fail(error);
  }
}());
