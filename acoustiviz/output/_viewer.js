// A small self-contained WebGL viewer for the scenes exported by acoustiviz.output.html.
// The page embeds SCENE (JSON): layers of triangles or line segments with a fixed colour or one
// scalar array per frame, a colour map, its limits and the frame times. Drag to rotate, wheel to
// zoom, double-click to reset; a slider steps through the frames.
(function () {
  "use strict";
  const S = JSON.parse(document.getElementById("scene-data").textContent);
  const status = document.getElementById("status");
  function decode(b64, Type) {
    const s = atob(b64);
    const u = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) u[i] = s.charCodeAt(i);
    return new Type(u.buffer);
  }
  const lut = decode(S.lut, Uint8Array);
  const nanRGB = S.nan_color;
  function hex(c) {
    return [parseInt(c.slice(1, 3), 16) / 255, parseInt(c.slice(3, 5), 16) / 255, parseInt(c.slice(5, 7), 16) / 255];
  }
  function colours(values, out) {
    const lo = S.clim[0], span = S.clim[1] - S.clim[0];
    for (let i = 0; i < values.length; i++) {
      const v = values[i];
      if (!isFinite(v)) { out[3 * i] = nanRGB[0]; out[3 * i + 1] = nanRGB[1]; out[3 * i + 2] = nanRGB[2]; continue; }
      let k = Math.round(255 * (v - lo) / span);
      k = k < 0 ? 0 : (k > 255 ? 255 : k);
      out[3 * i] = lut[3 * k] / 255; out[3 * i + 1] = lut[3 * k + 1] / 255; out[3 * i + 2] = lut[3 * k + 2] / 255;
    }
    return out;
  }

  // ------------------------------------------------------------------ colour bar
  function drawBar() {
    const bar = document.getElementById("colourbar");
    if (!S.colorbar) { bar.style.display = "none"; return; }
    const ctx = bar.getContext("2d");
    const w = bar.width, h = bar.height, x0 = 10, bw = 22, y0 = 30, bh = h - 60;
    ctx.clearRect(0, 0, w, h);
    for (let j = 0; j < bh; j++) {
      const k = Math.round(255 * (1 - j / (bh - 1)));
      ctx.fillStyle = `rgb(${lut[3 * k]},${lut[3 * k + 1]},${lut[3 * k + 2]})`;
      ctx.fillRect(x0, y0 + j, bw, 1);
    }
    ctx.strokeStyle = "#333"; ctx.strokeRect(x0, y0, bw, bh);
    ctx.fillStyle = "#111"; ctx.font = "13px sans-serif"; ctx.textBaseline = "middle";
    for (let q = 0; q <= 4; q++) {
      const v = S.clim[0] + (S.clim[1] - S.clim[0]) * q / 4;
      const y = y0 + bh * (1 - q / 4);
      ctx.fillText(Number(v.toPrecision(3)).toString(), x0 + bw + 6, y);
      ctx.fillRect(x0 + bw, y, 4, 1);
    }
    document.getElementById("colourbar-title").textContent = S.colorbar;
  }

  // ------------------------------------------------------------------ WebGL
  const canvas = document.getElementById("view");
  const gl = canvas.getContext("webgl", { antialias: true, preserveDrawingBuffer: true, alpha: false });
  if (!gl || !gl.getExtension("OES_element_index_uint")) {
    document.getElementById("nogl").style.display = "block";
    status.textContent = "no-webgl";
    drawBar();
    return;
  }
  const vs = `attribute vec3 aPos; attribute vec3 aNormal; attribute vec3 aColour;
    uniform mat4 uProj; uniform mat4 uView; varying vec3 vColour; varying vec3 vN;
    void main() { vec4 p = uView * vec4(aPos, 1.0); gl_Position = uProj * p; vColour = aColour;
                  vN = (uView * vec4(aNormal, 0.0)).xyz; }`;
  const fs = `precision mediump float; varying vec3 vColour; varying vec3 vN; uniform float uLit; uniform float uAlpha;
    void main() { float d = 1.0; if (uLit > 0.5 && dot(vN, vN) > 0.0) { d = 0.4 + 0.6 * abs(normalize(vN).z); }
                  gl_FragColor = vec4(vColour * d, uAlpha); }`;
  function shader(type, src) {
    const s = gl.createShader(type); gl.shaderSource(s, src); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }
  const prog = gl.createProgram();
  gl.attachShader(prog, shader(gl.VERTEX_SHADER, vs));
  gl.attachShader(prog, shader(gl.FRAGMENT_SHADER, fs));
  gl.linkProgram(prog);
  gl.useProgram(prog);
  const loc = {
    pos: gl.getAttribLocation(prog, "aPos"), normal: gl.getAttribLocation(prog, "aNormal"),
    colour: gl.getAttribLocation(prog, "aColour"), proj: gl.getUniformLocation(prog, "uProj"),
    view: gl.getUniformLocation(prog, "uView"), lit: gl.getUniformLocation(prog, "uLit"),
    alpha: gl.getUniformLocation(prog, "uAlpha"),
  };
  function buffer(data, target) {
    const b = gl.createBuffer(); gl.bindBuffer(target || gl.ARRAY_BUFFER, b);
    gl.bufferData(target || gl.ARRAY_BUFFER, data, gl.STATIC_DRAW); return b;
  }
  let nTriangles = 0;
  const layers = S.layers.map(function (L) {
    const pos = decode(L.positions, Float32Array);
    const n = pos.length / 3;
    const idx = decode(L.indices, Uint32Array);
    const normals = L.normals ? decode(L.normals, Float32Array) : new Float32Array(3 * n);
    const frames = L.scalars ? L.scalars.map(function (b) { return decode(b, Float32Array); }) : null;
    const col = new Float32Array(3 * n);
    if (!frames) { const c = hex(L.color); for (let i = 0; i < n; i++) col.set(c, 3 * i); }
    if (L.kind === "triangles") nTriangles += idx.length / 3;
    return {
      kind: L.kind, opacity: L.opacity, lit: L.lit, frames: frames, colours: col, count: idx.length,
      pos: buffer(pos), normal: buffer(normals), colour: buffer(frames ? colours(frames[0], col) : col),
      index: buffer(idx, gl.ELEMENT_ARRAY_BUFFER),
    };
  });

  // ------------------------------------------------------------------ camera
  const target = S.target, radius = S.radius;
  const home = { az: Math.atan2(S.direction[1], S.direction[0]),
                 el: Math.atan2(S.direction[2], Math.hypot(S.direction[0], S.direction[1])), dist: 2.6 * radius };
  const cam = Object.assign({}, home);
  function perspective(fovy, aspect, near, far) {
    const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
    return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0]);
  }
  function lookAt(eye, c, up) {
    let z = [eye[0] - c[0], eye[1] - c[1], eye[2] - c[2]];
    let l = Math.hypot(z[0], z[1], z[2]); z = z.map(function (v) { return v / l; });
    let x = [up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]];
    l = Math.hypot(x[0], x[1], x[2]); x = x.map(function (v) { return v / l; });
    const y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]];
    const d = function (a) { return -(a[0] * eye[0] + a[1] * eye[1] + a[2] * eye[2]); };
    return new Float32Array([x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0, d(x), d(y), d(z), 1]);
  }
  function draw() {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * dpr)), h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    gl.viewport(0, 0, w, h);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    const ce = Math.cos(cam.el);
    const eye = [target[0] + cam.dist * ce * Math.cos(cam.az), target[1] + cam.dist * ce * Math.sin(cam.az),
                 target[2] + cam.dist * Math.sin(cam.el)];
    gl.uniformMatrix4fv(loc.proj, false, perspective(0.6, w / h, cam.dist / 100, cam.dist * 10));
    gl.uniformMatrix4fv(loc.view, false, lookAt(eye, target, [0, 0, 1]));
    const order = layers.filter(function (L) { return L.opacity >= 1; })
      .concat(layers.filter(function (L) { return L.opacity < 1; }));
    for (const L of order) {
      const transparent = L.opacity < 1;
      if (transparent) { gl.enable(gl.BLEND); gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA); gl.depthMask(false); }
      gl.bindBuffer(gl.ARRAY_BUFFER, L.pos); gl.enableVertexAttribArray(loc.pos);
      gl.vertexAttribPointer(loc.pos, 3, gl.FLOAT, false, 0, 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, L.normal); gl.enableVertexAttribArray(loc.normal);
      gl.vertexAttribPointer(loc.normal, 3, gl.FLOAT, false, 0, 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, L.colour); gl.enableVertexAttribArray(loc.colour);
      gl.vertexAttribPointer(loc.colour, 3, gl.FLOAT, false, 0, 0);
      gl.uniform1f(loc.lit, L.lit ? 1 : 0);
      gl.uniform1f(loc.alpha, L.opacity);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, L.index);
      gl.drawElements(L.kind === "lines" ? gl.LINES : gl.TRIANGLES, L.count, gl.UNSIGNED_INT, 0);
      if (transparent) { gl.disable(gl.BLEND); gl.depthMask(true); }
    }
  }
  let pending = false;
  function redraw() { if (!pending) { pending = true; requestAnimationFrame(function () { pending = false; draw(); }); } }

  // ------------------------------------------------------------------ interaction
  let drag = null;
  canvas.addEventListener("pointerdown", function (e) { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener("pointerup", function () { drag = null; });
  canvas.addEventListener("pointermove", function (e) {
    if (!drag) return;
    cam.az -= 0.008 * (e.clientX - drag[0]);
    cam.el = Math.max(-1.55, Math.min(1.55, cam.el + 0.008 * (e.clientY - drag[1])));
    drag = [e.clientX, e.clientY]; redraw();
  });
  canvas.addEventListener("wheel", function (e) {
    e.preventDefault(); cam.dist *= Math.exp(0.001 * e.deltaY); redraw();
  }, { passive: false });
  canvas.addEventListener("dblclick", function () { Object.assign(cam, home); redraw(); });
  window.addEventListener("resize", redraw);

  const slider = document.getElementById("frame");
  function setFrame(q) {
    for (const L of layers) {
      if (!L.frames) continue;
      gl.bindBuffer(gl.ARRAY_BUFFER, L.colour);
      gl.bufferData(gl.ARRAY_BUFFER, colours(L.frames[q], L.colours), gl.STATIC_DRAW);
    }
    document.getElementById("frame-label").textContent = S.frame_labels[q] || "";
    redraw();
  }
  if (S.frame_labels.length > 1) {
    slider.max = S.frame_labels.length - 1;
    slider.addEventListener("input", function () { setFrame(Number(slider.value)); });
  } else {
    slider.style.display = "none";
  }
  setFrame(0);
  drawBar();
  draw();
  status.textContent = "rendered " + nTriangles + " triangles";
})();
