// The 3D view of report.html: a canvas-2D renderer of a convex hull (see src/report/html.rs for
// why back-face culling alone gives exact visibility). HULL is the data written by Rust.
(function () {
  'use strict';
  var status = document.getElementById('status');
  if (!HULL) {
    document.getElementById('hullsection').style.display = 'none';
    status.setAttribute('data-status', 'drawn');
    return;
  }
  var canvas = document.getElementById('hull');
  var ctx = canvas.getContext('2d');
  var W = canvas.width, H = canvas.height;
  var V = HULL.vertices, F = HULL.facets, E = HULL.equilibria, A = HULL.arcs, FL = HULL.flocks;
  var rmax = 0;
  V.forEach(function (p) { rmax = Math.max(rmax, Math.hypot(p[0], p[1], p[2])); });
  // view: rotation matrix R (rows = screen x, screen y up, towards the viewer), zoom
  var R0 = [[1, 0, 0], [0, 0, 1], [0, -1, 0]];
  var R = R0.map(function (r) { return r.slice(); });
  var zoom = 1;
  var KIND_MARK = { stable: 'circle', unstable: 'square', saddle: 'diamond' };

  function mul(a, b) {
    var c = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
    for (var i = 0; i < 3; i++) for (var j = 0; j < 3; j++) for (var k = 0; k < 3; k++) c[i][j] += a[i][k] * b[k][j];
    return c;
  }
  function rot(axis, ang) {
    var c = Math.cos(ang), s = Math.sin(ang);
    if (axis === 0) return [[1, 0, 0], [0, c, -s], [0, s, c]];
    return [[c, 0, s], [0, 1, 0], [-s, 0, c]];
  }
  function apply(p) {
    return [R[0][0] * p[0] + R[0][1] * p[1] + R[0][2] * p[2],
            R[1][0] * p[0] + R[1][1] * p[1] + R[1][2] * p[2],
            R[2][0] * p[0] + R[2][1] * p[1] + R[2][2] * p[2]];
  }
  function screen(p) {
    var q = apply(p), s = zoom * 0.45 * Math.min(W, H) / rmax;
    return [W / 2 + q[0] * s, H / 2 - q[1] * s];
  }
  function hex(c) { return [parseInt(c.substr(1, 2), 16), parseInt(c.substr(3, 2), 16), parseInt(c.substr(5, 2), 16)]; }
  var flockRgb = FL.map(function (f) { return hex(f.color); });

  var front = new Uint8Array(F.length);
  var marks = [];
  function draw() {
    ctx.fillStyle = '#ffffff';
    ctx.fillRect(0, 0, W, H);
    var light = [0.35, 0.45, 0.82];
    for (var f = 0; f < F.length; f++) {
      var n = apply(F[f].n);
      front[f] = n[2] > 0 ? 1 : 0;
      if (!front[f]) continue;
      var lam = Math.max(0, n[0] * light[0] + n[1] * light[1] + n[2] * light[2]);
      var shade = 0.55 + 0.45 * lam;
      var base = F[f].flock === null ? [170, 170, 170] : flockRgb[F[f].flock];
      ctx.fillStyle = 'rgb(' + base.map(function (c) { return Math.round(Math.min(255, (0.75 * c + 64) * shade)); }).join(',') + ')';
      ctx.beginPath();
      var vs = F[f].v;
      for (var k = 0; k < vs.length; k++) {
        var s = screen(V[vs[k]]);
        if (k === 0) ctx.moveTo(s[0], s[1]); else ctx.lineTo(s[0], s[1]);
      }
      ctx.closePath();
      ctx.fill();
      ctx.strokeStyle = ctx.fillStyle;  // hide hairline seams between facets
      ctx.lineWidth = 0.6;
      ctx.stroke();
    }
    function seen(on) { for (var i = 0; i < on.length; i++) if (front[on[i]]) return true; return false; }
    ctx.strokeStyle = 'rgba(0,0,0,0.6)';
    ctx.lineWidth = 1;
    ctx.beginPath();
    A.forEach(function (seg) {
      if (!seen(seg.on)) return;
      var a = screen(seg.a), b = screen(seg.b);
      ctx.moveTo(a[0], a[1]);
      ctx.lineTo(b[0], b[1]);
    });
    ctx.stroke();
    marks = [];
    E.forEach(function (e) {
      if (!seen(e.on)) return;
      var s = screen(e.p);
      marks.push({ x: s[0], y: s[1], e: e });
      mark(ctx, KIND_MARK[e.kind], s[0], s[1], 6, FL[e.flock].color);
    });
  }
  function mark(c, shape, x, y, r, fill) {
    c.beginPath();
    if (shape === 'circle') c.arc(x, y, r, 0, 2 * Math.PI);
    else if (shape === 'square') c.rect(x - r + 1, y - r + 1, 2 * r - 2, 2 * r - 2);
    else { c.moveTo(x, y - r - 1); c.lineTo(x + r + 1, y); c.lineTo(x, y + r + 1); c.lineTo(x - r - 1, y); c.closePath(); }
    c.fillStyle = fill;
    c.fill();
    c.strokeStyle = '#000';
    c.lineWidth = 1;
    c.stroke();
  }
  function legend() {
    var el = document.getElementById('legend');
    var html = '<b>Micro-equilibria</b><br>';
    var names = { stable: 'stable (on a facet)', unstable: 'unstable (at a vertex)', saddle: 'saddle (on an edge)' };
    ['stable', 'unstable', 'saddle'].forEach(function (k) {
      var n = E.filter(function (e) { return e.kind === k; }).length;
      var svg = { circle: '<circle cx="8" cy="8" r="6"/>', square: '<rect x="3" y="3" width="10" height="10"/>',
                  diamond: '<polygon points="8,1 15,8 8,15 1,8"/>' }[KIND_MARK[k]];
      html += '<svg width="16" height="16"><g fill="#ccc" stroke="#000">' + svg + '</g></svg>' + names[k] + ': ' + n + '<br>';
    });
    html += '<svg width="16" height="16"><line x1="0" y1="8" x2="16" y2="8" stroke="#555"/></svg>Morse–Smale arc<br><br>';
    html += '<b>Flocks</b> (facet tint and mark fill)<br>';
    FL.forEach(function (f) {
      html += '<span class="sw" style="background:' + f.color + '"></span>F' + f.id + ': ' + f.kind + ' flock (' +
        f.counts[0] + ' S, ' + f.counts[1] + ' U, ' + f.counts[2] + ' H)<br>';
    });
    el.innerHTML = html;
  }
  function fmt(x) { return Math.abs(x) >= 1e-3 && Math.abs(x) < 1e7 ? String(+x.toPrecision(5)) : x.toExponential(3); }

  var tip = document.getElementById('tip');
  var drag = null;
  canvas.addEventListener('mousedown', function (ev) { drag = [ev.clientX, ev.clientY]; canvas.style.cursor = 'grabbing'; });
  window.addEventListener('mouseup', function () { drag = null; canvas.style.cursor = 'grab'; });
  canvas.addEventListener('mousemove', function (ev) {
    if (drag) {
      var dx = ev.clientX - drag[0], dy = ev.clientY - drag[1];
      drag = [ev.clientX, ev.clientY];
      R = mul(rot(0, dy * 0.01), mul(rot(1, dx * 0.01), R));
      tip.style.display = 'none';
      draw();
      return;
    }
    var b = canvas.getBoundingClientRect();
    var x = (ev.clientX - b.left) * W / b.width, y = (ev.clientY - b.top) * H / b.height;
    var best = null, bd = 81;
    marks.forEach(function (m) { var d = (m.x - x) * (m.x - x) + (m.y - y) * (m.y - y); if (d < bd) { bd = d; best = m; } });
    if (!best) { tip.style.display = 'none'; return; }
    var e = best.e, f = FL[e.flock];
    var rocking = e.kind === 'stable' && f.kind !== 'stable' ? '\nrocking equilibrium: stable, inside a ' + f.kind + ' flock' : '';
    tip.textContent = e.kind + ' micro-equilibrium #' + e.index + ' (' + e.site + ')\nR = ' + fmt(e.r) + ' ' + HULL.unit +
      ' (R/R_max = ' + (e.r / HULL.r_max).toFixed(4) + ')\nflock F' + f.id + ' (' + f.kind + ')' + rocking;
    tip.style.left = (ev.clientX + 14) + 'px';
    tip.style.top = (ev.clientY + 14) + 'px';
    tip.style.display = 'block';
  });
  canvas.addEventListener('mouseleave', function () { tip.style.display = 'none'; });
  canvas.addEventListener('wheel', function (ev) {
    ev.preventDefault();
    zoom = Math.min(20, Math.max(0.2, zoom * Math.exp(-ev.deltaY * 0.001)));
    draw();
  }, { passive: false });
  canvas.addEventListener('dblclick', function () { R = R0.map(function (r) { return r.slice(); }); zoom = 1; draw(); });

  legend();
  draw();
  // self-check for the headless test: how many pixels differ from the white background
  var px = ctx.getImageData(0, 0, W, H).data, nonblank = 0;
  for (var i = 0; i < px.length; i += 4) if (px[i] < 250 || px[i + 1] < 250 || px[i + 2] < 250) nonblank++;
  status.setAttribute('data-nonblank', String(nonblank));
  // and the tooltip: hover the first visible mark (a synthetic mouse event) and read the tip
  if (marks.length > 0) {
    var m = marks[0], b = canvas.getBoundingClientRect();
    canvas.dispatchEvent(new MouseEvent('mousemove', { clientX: b.left + m.x * b.width / W, clientY: b.top + m.y * b.height / H }));
    var text = tip.style.display === 'block' ? tip.textContent : '';
    status.setAttribute('data-tooltip', text.split('\n').join(' | '));
    tip.style.display = 'none';
  }
  if (status.getAttribute('data-status') !== 'error') status.setAttribute('data-status', 'drawn');
})();
