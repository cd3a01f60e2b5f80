// The 3D replay: a 2D canvas drawn with the painter's algorithm (far triangles first).
(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('replay-data').textContent);
  document.title = data.title;
  var statusEl = document.getElementById('status');
  function report(extra) {
    statusEl.textContent = (window.__replayDrawn ? 'drawn ' + window.__replayTriangles + ' triangles' : 'not drawn') +
      '; errors: ' + window.__errors + (extra ? '; ' + extra : '');
  }
  var canvas = document.getElementById('replay-canvas');
  if (!canvas || data.runs.length === 0) { report('no replay'); return; }
  var ctx = canvas.getContext('2d');
  var runSel = document.getElementById('replay-run');
  var playBtn = document.getElementById('replay-play');
  var speedSel = document.getElementById('replay-speed');
  var slider = document.getElementById('replay-slider');
  var timeEl = document.getElementById('replay-time');
  var Q = data.quantum;

  // Same look as the PNG snapshots (src/render).
  var CLOTH_FRONT = [0.36, 0.58, 0.88], CLOTH_BACK = [0.93, 0.62, 0.32];
  var OBSTACLE = [0.8, 0.8, 0.8], GROUND = [1.0, 1.0, 1.0];
  var EDGE = 'rgba(20, 26, 41, 0.7)';
  var AMBIENT = 0.35, DIFFUSE = 0.65;
  var LIGHT = normalize([0.1, -0.8, 1.2]);
  var ELEVATION = 30 * Math.PI / 180, AZIMUTH = -55 * Math.PI / 180;
  var CLOTH_DEPTH_BIAS = 0.04; // share of the scene's bounding radius

  function normalize(a) { var n = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / n, a[1] / n, a[2] / n]; }
  function bounds(p, b) {
    for (var i = 0; i < p.length; i += 3) {
      for (var k = 0; k < 3; k++) {
        var x = p[i + k] * Q;
        if (x < b[0][k]) b[0][k] = x;
        if (x > b[1][k]) b[1][k] = x;
      }
    }
  }
  var obstacles = data.obstacles.map(function (o) {
    var b = [[Infinity, Infinity, Infinity], [-Infinity, -Infinity, -Infinity]];
    bounds(o.p, b);
    var span = Math.max(b[1][0] - b[0][0], b[1][1] - b[0][1]);
    return { p: o.p, f: o.f, flat: !(b[1][2] - b[0][2] > 1e-4 * span), b: b };
  });

  // One camera for every run: framing all frames of all runs and the solid obstacles, moving
  // ones where they stand in every frame (the corners of their bounding boxes, posed).
  var box = [[Infinity, Infinity, Infinity], [-Infinity, -Infinity, -Infinity]];
  obstacles.forEach(function (o) {
    var c = [];
    for (var i = 0; i < 8; i++) {
      for (var k = 0; k < 3; k++) c.push(o.b[(i >> k) & 1][k] / Q);
    }
    o.corners = c;
  });
  data.runs.forEach(function (r) {
    r.frames.forEach(function (f) {
      bounds(f.p, box);
      if (f.o) obstacles.forEach(function (o, k) { if (!o.flat) bounds(posed(o.corners, f.o[k]), box); });
    });
  });
  obstacles.forEach(function (o) { if (!o.flat) bounds(o.p, box); });
  if (!(box[0][0] <= box[1][0])) box = [[-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]];
  var center = [0, 1, 2].map(function (k) { return 0.5 * (box[0][k] + box[1][k]); });
  var radius = Math.max(0.5 * Math.hypot(box[1][0] - box[0][0], box[1][1] - box[0][1], box[1][2] - box[0][2]), 1e-3);
  var view = { yaw: AZIMUTH, pitch: ELEVATION, zoom: 1 };

  function camera() {
    var ce = Math.cos(view.pitch), toEye = [ce * Math.cos(view.yaw), ce * Math.sin(view.yaw), Math.sin(view.pitch)];
    var dist = 3 * radius;
    var eye = [0, 1, 2].map(function (k) { return center[k] + dist * toEye[k]; });
    var fwd = toEye.map(function (c) { return -c; });
    var right = normalize([fwd[1], -fwd[0], 0]);
    if (!isFinite(right[0]) || Math.hypot(right[0], right[1]) < 1e-6) right = [1, 0, 0];
    var up = [right[1] * fwd[2] - right[2] * fwd[1], right[2] * fwd[0] - right[0] * fwd[2], right[0] * fwd[1] - right[1] * fwd[0]];
    return { eye: eye, fwd: fwd, right: right, up: up, focal: view.zoom * fitFocal, near: 0.01 * radius };
  }
  // Focal length (pixels) at which the box, seen from the initial view, fills 90% of the canvas.
  var fitFocal = 1;
  (function () {
    var cam = camera(), fx = 1e-6, fy = 1e-6;
    for (var k = 0; k < 8; k++) {
      var p = [0, 1, 2].map(function (i) { return box[(k >> i) & 1][i] - cam.eye[i]; });
      var z = p[0] * cam.fwd[0] + p[1] * cam.fwd[1] + p[2] * cam.fwd[2];
      fx = Math.max(fx, Math.abs(p[0] * cam.right[0] + p[1] * cam.right[1] + p[2] * cam.right[2]) / z);
      fy = Math.max(fy, Math.abs(p[0] * cam.up[0] + p[1] * cam.up[1] + p[2] * cam.up[2]) / z);
    }
    fitFocal = 0.45 * Math.min(canvas.width / fx, canvas.height / fy);
  })();

  function shadeColor(base, s) {
    return 'rgb(' + Math.round(255 * base[0] * s) + ',' + Math.round(255 * base[1] * s) + ',' + Math.round(255 * base[2] * s) + ')';
  }

  // Appends the visible triangles of one mesh to `out`.
  function collect(cam, p, f, kind, out) {
    var n = p.length / 3, sx = new Float32Array(n), sy = new Float32Array(n), sz = new Float32Array(n);
    var e = cam.eye, W2 = canvas.width / 2, H2 = canvas.height / 2;
    for (var i = 0; i < n; i++) {
      var dx = p[3 * i] * Q - e[0], dy = p[3 * i + 1] * Q - e[1], dz = p[3 * i + 2] * Q - e[2];
      var z = dx * cam.fwd[0] + dy * cam.fwd[1] + dz * cam.fwd[2];
      sz[i] = z;
      sx[i] = W2 + cam.focal * (dx * cam.right[0] + dy * cam.right[1] + dz * cam.right[2]) / z;
      sy[i] = H2 - cam.focal * (dx * cam.up[0] + dy * cam.up[1] + dz * cam.up[2]) / z;
    }
    for (var t = 0; t < f.length; t += 3) {
      var a = f[t], b = f[t + 1], c = f[t + 2];
      if (sz[a] < cam.near || sz[b] < cam.near || sz[c] < cam.near) continue;
      var ux = (p[3 * b] - p[3 * a]) * Q, uy = (p[3 * b + 1] - p[3 * a + 1]) * Q, uz = (p[3 * b + 2] - p[3 * a + 2]) * Q;
      var vx = (p[3 * c] - p[3 * a]) * Q, vy = (p[3 * c + 1] - p[3 * a + 1]) * Q, vz = (p[3 * c + 2] - p[3 * a + 2]) * Q;
      var nrm = normalize([uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx]);
      var toFace = [p[3 * a] * Q - e[0], p[3 * a + 1] * Q - e[1], p[3 * a + 2] * Q - e[2]];
      var front = nrm[0] * toFace[0] + nrm[1] * toFace[1] + nrm[2] * toFace[2] < 0;
      if (!front && kind !== 'cloth') {
        if (kind === 'solid') continue; // closed meshes: back faces are hidden anyway
        nrm = [-nrm[0], -nrm[1], -nrm[2]];
      } else if (!front) {
        nrm = [-nrm[0], -nrm[1], -nrm[2]];
      }
      var s = AMBIENT + DIFFUSE * Math.max(0, nrm[0] * LIGHT[0] + nrm[1] * LIGHT[1] + nrm[2] * LIGHT[2]);
      var base = kind === 'cloth' ? (front ? CLOTH_FRONT : CLOTH_BACK) : (kind === 'flat' ? GROUND : OBSTACLE);
      // Painter's order, biased for contact: obstacle triangles sort by their farthest corner
      // and the cloth by its centroid brought nearer by a small share of the scene size, so the
      // cloth lying on an obstacle is painted after the obstacle triangles just under it.
      var depth = kind === 'cloth' ? (sz[a] + sz[b] + sz[c]) / 3 - CLOTH_DEPTH_BIAS * radius
        : Math.max(sz[a], sz[b], sz[c]);
      out.push({ d: depth, x0: sx[a], y0: sy[a], x1: sx[b], y1: sy[b], x2: sx[c], y2: sy[c], color: shadeColor(base, s), cloth: kind === 'cloth' });
    }
  }

  var runIndex = 0, frameIndex = 0;

  // Positions (in quanta) moved by a rigid motion m: row-major rotation, then translation (m).
  function posed(p, m) {
    var out = new Float64Array(p.length);
    for (var i = 0; i < p.length; i += 3) {
      var x = p[i] * Q, y = p[i + 1] * Q, z = p[i + 2] * Q;
      for (var r = 0; r < 3; r++) {
        out[i + r] = (m[3 * r] * x + m[3 * r + 1] * y + m[3 * r + 2] * z + m[9 + r]) / Q;
      }
    }
    return out;
  }

  function draw() {
    var run = data.runs[runIndex], frame = run.frames[frameIndex];
    var cam = camera();
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    var flat = [], tris = [];
    obstacles.forEach(function (o, k) {
      var p = frame && frame.o ? posed(o.p, frame.o[k]) : o.p;
      collect(cam, p, o.f, o.flat ? 'flat' : 'solid', o.flat ? flat : tris);
    });
    if (frame) collect(cam, frame.p, run.topologies[frame.k], 'cloth', tris);
    tris.sort(function (u, v) { return v.d - u.d; });
    var all = flat.concat(tris); // the ground first, under everything
    ctx.lineJoin = 'round';
    for (var i = 0; i < all.length; i++) {
      var t = all[i];
      ctx.beginPath();
      ctx.moveTo(t.x0, t.y0);
      ctx.lineTo(t.x1, t.y1);
      ctx.lineTo(t.x2, t.y2);
      ctx.closePath();
      ctx.fillStyle = t.color;
      ctx.fill();
      ctx.lineWidth = t.cloth ? 0.8 : 0.6;
      ctx.strokeStyle = t.cloth ? EDGE : t.color; // obstacles: stroke hides the seams
      ctx.stroke();
    }
    var time = run.times[frameIndex] || 0;
    timeEl.textContent = 't = ' + time.toFixed(3) + ' s (frame ' + (frameIndex + 1) + '/' + run.frames.length + ', ' +
      (frame ? run.topologies[frame.k].length / 3 : 0) + ' cloth triangles)';
    if (!window.__replayDrawn) {
      window.__replayDrawn = true;
      window.__replayTriangles = all.length;
      report('view radius ' + radius.toFixed(3) + ' m');
    }
  }

  data.runs.forEach(function (r, k) {
    var o = document.createElement('option');
    o.value = String(k);
    o.textContent = r.label;
    runSel.appendChild(o);
  });

  function setRun(k) {
    var t = data.runs[runIndex].times[frameIndex] || 0;
    runIndex = k;
    var run = data.runs[k];
    slider.max = String(Math.max(run.frames.length - 1, 0));
    frameIndex = frameAt(run, t);
    slider.value = String(frameIndex);
    draw();
  }
  // Index of the last frame at or before time t.
  function frameAt(run, t) {
    var i = 0;
    while (i + 1 < run.times.length && run.times[i + 1] <= t + 1e-12) i++;
    return i;
  }

  var playing = false, simTime = 0, lastWall = 0;
  function tick(now) {
    if (!playing) return;
    var run = data.runs[runIndex], end = run.times[run.times.length - 1] || 0;
    simTime += (now - lastWall) / 1000 * parseFloat(speedSel.value);
    lastWall = now;
    if (simTime > end) simTime = 0;
    var k = frameAt(run, simTime);
    if (k !== frameIndex) { frameIndex = k; slider.value = String(k); draw(); }
    requestAnimationFrame(tick);
  }
  playBtn.addEventListener('click', function () {
    playing = !playing;
    playBtn.textContent = playing ? 'Pause' : 'Play';
    if (playing) {
      simTime = data.runs[runIndex].times[frameIndex] || 0;
      lastWall = performance.now();
      requestAnimationFrame(tick);
    }
  });
  slider.addEventListener('input', function () {
    frameIndex = parseInt(slider.value, 10) || 0;
    simTime = data.runs[runIndex].times[frameIndex] || 0;
    draw();
  });
  runSel.addEventListener('change', function () { setRun(parseInt(runSel.value, 10) || 0); });

  var drag = null;
  canvas.addEventListener('pointerdown', function (e) {
    drag = { x: e.clientX, y: e.clientY };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', function (e) {
    if (!drag) return;
    view.yaw -= (e.clientX - drag.x) * 0.01;
    view.pitch = Math.max(-1.5, Math.min(1.5, view.pitch + (e.clientY - drag.y) * 0.01));
    drag = { x: e.clientX, y: e.clientY };
    draw();
  });
  canvas.addEventListener('pointerup', function () { drag = null; });
  canvas.addEventListener('wheel', function (e) {
    e.preventDefault();
    view.zoom = Math.max(0.2, Math.min(20, view.zoom * Math.exp(-e.deltaY * 0.001)));
    draw();
  }, { passive: false });
  canvas.addEventListener('dblclick', function () {
    view = { yaw: AZIMUTH, pitch: ELEVATION, zoom: 1 };
    draw();
  });

  // A link like report.html#t=0.5 opens the replay at that time (s).
  var m = /[#&]t=([0-9.eE+-]+)/.exec(location.hash);
  if (m) {
    var t0 = parseFloat(m[1]);
    frameIndex = frameAt(data.runs[0], isFinite(t0) ? t0 : 0);
  }
  setRun(0);
})();
