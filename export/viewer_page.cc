#include "export/viewer_page.h"

#include <algorithm>
#include <cmath>

#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/text_format.h"
#include "export/previews.h"

namespace mesocap {

namespace fs = std::filesystem;

namespace {

std::string Base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = uint32_t(uint8_t(bytes[i])) << 16 | (i + 1 < bytes.size() ? uint32_t(uint8_t(bytes[i + 1])) << 8 : 0) |
                       (i + 2 < bytes.size() ? uint32_t(uint8_t(bytes[i + 2])) : 0);
    out += table[n >> 18 & 63];
    out += table[n >> 12 & 63];
    out += i + 1 < bytes.size() ? table[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? table[n & 63] : '=';
  }
  return out;
}

// `image` (values in [0, 1]) as a PNG data URI, 8-bit in `format` (sRGB for pictures, linear
// for data such as PTM coefficients).
StatusOr<std::string> PngDataUri(const Image& image, PixelFormat format, const fs::path& scratch, const std::string& name) {
  const fs::path file = scratch / (name + ".png");
  MESOCAP_RETURN_IF_ERROR(WriteImage(file, image, {.format = format}));
  auto bytes = ReadTextFile(file);
  std::error_code ec;
  fs::remove(file, ec);
  if (!bytes.ok()) return bytes.status();
  return "data:image/png;base64," + Base64(*bytes);
}

// Coefficient k of every channel as an RGB image in [0, 1], with the range it maps back to.
struct CoefficientPlane {
  Image image;
  float lo = 0, hi = 1;
};

std::vector<CoefficientPlane> PtmPlanes(const Ptm& ptm) {
  std::vector<CoefficientPlane> planes(kPtmCoefficients);
  const int w = ptm.width(), h = ptm.height();
  const auto coefficient = [&](int x, int y, int c, int k) {
    return ptm.format == PtmFormat::kLrgb ? ptm.coefficients.at(x, y, k) * ptm.rgb.at(x, y, c)
                                          : ptm.coefficients.at(x, y, c * kPtmCoefficients + k);
  };
  for (int k = 0; k < kPtmCoefficients; ++k) {
    CoefficientPlane& p = planes[k];
    p.lo = 1e30f, p.hi = -1e30f;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) p.lo = std::min(p.lo, coefficient(x, y, c, k)), p.hi = std::max(p.hi, coefficient(x, y, c, k));
    if (!(p.hi > p.lo)) p.hi = p.lo + 1;
    p.image = Image(w, h, 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) p.image.at(x, y, c) = (coefficient(x, y, c, k) - p.lo) / (p.hi - p.lo);
  }
  return planes;
}

// The BTF's slices as tiles of an atlas, `columns` to a row, under one display exposure.
Image SliceAtlas(const std::vector<ViewerSlice>& slices, int tile, int columns) {
  const int rows = (int(slices.size()) + columns - 1) / columns;
  std::vector<const Image*> full;
  for (const ViewerSlice& s : slices) full.push_back(&s.image);
  const float scale = CommonDisplayScale(full, 0.995);
  Image atlas(columns * tile, rows * tile, 3);
  for (size_t k = 0; k < slices.size(); ++k) {
    const Image small = Thumbnail(slices[k].image, tile);
    const int ox = int(k % columns) * tile, oy = int(k / columns) * tile;
    for (int y = 0; y < std::min(tile, small.height()); ++y)
      for (int x = 0; x < tile; ++x)
        for (int c = 0; c < 3; ++c) atlas.at(ox + x, oy + y, c) = std::clamp(small.at(x, y, c) * scale, 0.0f, 1.0f);
  }
  return atlas;
}

const char* kViewerScript = R"JS(
(function () {
  const data = JSON.parse(document.getElementById('mesocap-viewer-data').textContent);
  let errors = 0;
  const countError = () => { errors++; document.body.dataset.errors = String(errors); };
  window.addEventListener('error', countError);
  const consoleError = console.error.bind(console);
  console.error = (...args) => { countError(); consoleError(...args); };
  document.body.dataset.errors = '0';

  const vertexSource = 'attribute vec2 p; varying vec2 uv; void main() { uv = vec2(0.5 * (p.x + 1.0), 0.5 * (1.0 - p.y)); gl_Position = vec4(p, 0.0, 1.0); }';
  function program(gl, fragmentSource) {
    const make = (type, source) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, source);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      return s;
    };
    const prog = gl.createProgram();
    gl.attachShader(prog, make(gl.VERTEX_SHADER, vertexSource));
    gl.attachShader(prog, make(gl.FRAGMENT_SHADER, fragmentSource));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
    gl.useProgram(prog);
    const buffer = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 1, -1, -1, 1, 1, 1]), gl.STATIC_DRAW);
    const p = gl.getAttribLocation(prog, 'p');
    gl.enableVertexAttribArray(p);
    gl.vertexAttribPointer(p, 2, gl.FLOAT, false, 0, 0);
    return prog;
  }
  function texture(gl, unit, image) {
    const t = gl.createTexture();
    gl.activeTexture(gl.TEXTURE0 + unit);
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB, gl.RGB, gl.UNSIGNED_BYTE, image);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  }
  const load = (uri) => new Promise((resolve, reject) => {
    const image = new Image();
    image.onload = () => resolve(image);
    image.onerror = () => reject(new Error('cannot decode an inlined image'));
    image.src = uri;
  });

  const viewers = [];
  let light = [0.0, 0.0];  // the light's x and y on the unit disk (z follows)

  async function ptmViewer(canvas, ptm) {
    const gl = canvas.getContext('webgl', { preserveDrawingBuffer: true });
    if (!gl) throw new Error('WebGL is not available');
    const prog = program(gl, `precision mediump float; varying vec2 uv;
      uniform sampler2D a0, a1, a2, a3, a4, a5; uniform float lo[6], hi[6]; uniform vec2 l; uniform float exposure;
      vec3 c(sampler2D t, int k) { vec3 v = texture2D(t, uv).rgb; if (k == 0) return lo[0] + v * (hi[0] - lo[0]);
        if (k == 1) return lo[1] + v * (hi[1] - lo[1]); if (k == 2) return lo[2] + v * (hi[2] - lo[2]);
        if (k == 3) return lo[3] + v * (hi[3] - lo[3]); if (k == 4) return lo[4] + v * (hi[4] - lo[4]); return lo[5] + v * (hi[5] - lo[5]); }
      void main() { vec3 v = c(a0, 0) * l.x * l.x + c(a1, 1) * l.y * l.y + c(a2, 2) * l.x * l.y + c(a3, 3) * l.x + c(a4, 4) * l.y + c(a5, 5);
        vec3 d = clamp(v * exposure, 0.0, 1.0); gl_FragColor = vec4(pow(d, vec3(1.0 / 2.2)), 1.0); }`);
    const images = await Promise.all(ptm.planes.map(load));
    images.forEach((image, k) => { texture(gl, k, image); gl.uniform1i(gl.getUniformLocation(prog, 'a' + k), k); });
    gl.uniform1fv(gl.getUniformLocation(prog, 'lo'), ptm.lo);
    gl.uniform1fv(gl.getUniformLocation(prog, 'hi'), ptm.hi);
    gl.uniform1f(gl.getUniformLocation(prog, 'exposure'), ptm.exposure);
    const ul = gl.getUniformLocation(prog, 'l');
    return { canvas, gl, draw() { gl.uniform2f(ul, light[0], light[1]); gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4); } };
  }

  async function btfViewer(canvas, btf, select) {
    const gl = canvas.getContext('webgl', { preserveDrawingBuffer: true });
    if (!gl) throw new Error('WebGL is not available');
    const prog = program(gl, `precision mediump float; varying vec2 uv; uniform sampler2D atlas;
      uniform vec2 tiles; uniform vec2 t0, t1, t2; uniform vec3 w;
      vec3 tile(vec2 t) { return texture2D(atlas, (t + clamp(uv, 0.002, 0.998)) / tiles).rgb; }
      void main() { gl_FragColor = vec4(w.x * tile(t0) + w.y * tile(t1) + w.z * tile(t2), 1.0); }`);
    texture(gl, 0, await load(btf.atlas));
    gl.uniform1i(gl.getUniformLocation(prog, 'atlas'), 0);
    gl.uniform2f(gl.getUniformLocation(prog, 'tiles'), btf.columns, btf.rows);
    const views = [];
    btf.slices.forEach((s, k) => {
      let v = views.find((v) => Math.abs(v.dir[0] - s.view[0]) + Math.abs(v.dir[1] - s.view[1]) + Math.abs(v.dir[2] - s.view[2]) < 1e-3);
      if (!v) { v = { dir: s.view, slices: [] }; views.push(v); }
      v.slices.push({ light: s.light, tile: [k % btf.columns, Math.floor(k / btf.columns)] });
    });
    views.forEach((v, k) => {
      const option = document.createElement('option');
      const theta = Math.acos(Math.min(1, v.dir[2])) * 180 / Math.PI, phi = (Math.atan2(v.dir[1], v.dir[0]) * 180 / Math.PI + 360) % 360;
      option.value = k;
      option.textContent = `view theta ${theta.toFixed(0)}, phi ${phi.toFixed(0)} deg`;
      select.appendChild(option);
    });
    select.addEventListener('change', () => viewers.forEach((v) => v.draw()));
    const u = ['t0', 't1', 't2'].map((n) => gl.getUniformLocation(prog, n));
    const uw = gl.getUniformLocation(prog, 'w');
    return { canvas, gl, draw() {
      const view = views[Number(select.value) || 0];
      const z = Math.sqrt(Math.max(0, 1 - light[0] * light[0] - light[1] * light[1]));
      const near = view.slices.map((s) => ({ s, d: Math.acos(Math.max(-1, Math.min(1, s.light[0] * light[0] + s.light[1] * light[1] + s.light[2] * z))) }))
        .sort((a, b) => a.d - b.d).slice(0, 3);
      while (near.length < 3) near.push(near[0]);
      const weights = near.map((n) => 1 / (n.d + 1e-3)), sum = weights.reduce((a, b) => a + b, 0);
      near.forEach((n, k) => gl.uniform2f(u[k], n.s.tile[0], n.s.tile[1]));
      gl.uniform3f(uw, weights[0] / sum, weights[1] / sum, weights[2] / sum);
      gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    } };
  }

  function setLight(x, y) {
    const r = Math.hypot(x, y);
    light = r > 0.98 ? [0.98 * x / r, 0.98 * y / r] : [x, y];
    document.getElementById('mesocap-viewer-light').textContent = `light x ${light[0].toFixed(2)}, y ${light[1].toFixed(2)}`;
    viewers.forEach((v) => v.draw());
  }
  function pixels(v) {
    const out = new Uint8Array(v.canvas.width * v.canvas.height * 4);
    v.gl.readPixels(0, 0, v.canvas.width, v.canvas.height, v.gl.RGBA, v.gl.UNSIGNED_BYTE, out);
    return out;
  }
  async function selfTest() {
    const result = { canvases: viewers.length, changed: [] };
    for (const v of viewers) {
      setLight(-0.6, 0.0);
      const a = pixels(v);
      setLight(0.6, 0.3);
      const b = pixels(v);
      let changed = 0;
      for (let i = 0; i < a.length; i += 4) if (Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]) > 6) changed++;
      result.changed.push(changed / (a.length / 4));
    }
    document.body.dataset.selftest = JSON.stringify(result);
  }

  (async () => {
    try {
      if (data.ptm) viewers.push(await ptmViewer(document.getElementById('mesocap-viewer-ptm'), data.ptm));
      if (data.btf) viewers.push(await btfViewer(document.getElementById('mesocap-viewer-btf'), data.btf,
                                                 document.getElementById('mesocap-viewer-view')));
      for (const v of viewers)
        v.canvas.addEventListener('mousemove', (e) => {
          const r = v.canvas.getBoundingClientRect();
          setLight(2 * (e.clientX - r.left) / r.width - 1, 1 - 2 * (e.clientY - r.top) / r.height);
        });
      setLight(0.3, 0.3);
      if (location.hash === '#selftest') await selfTest();
    } catch (e) {
      console.error('mesocap viewer: ' + e.message);
      document.body.dataset.selftest = JSON.stringify({ error: e.message });
    }
  })();
})();
)JS";

}  // namespace

StatusOr<std::string> ViewerHtml(const Ptm* ptm, const std::vector<ViewerSlice>& slices, int tile, const fs::path& scratch) {
  Json data = Json::object();
  if (ptm) {
    const std::vector<CoefficientPlane> planes = PtmPlanes(*ptm);
    Json uris = Json::array(), lo = Json::array(), hi = Json::array();
    for (int k = 0; k < kPtmCoefficients; ++k) {
      auto uri = PngDataUri(planes[k].image, PixelFormat::kUint8Linear, scratch, "ptm_a" + std::to_string(k));
      if (!uri.ok()) return uri.status();
      uris.push_back(*uri);
      lo.push_back(planes[k].lo);
      hi.push_back(planes[k].hi);
    }
    const float exposure = DisplayScale(RelightPtm(*ptm, Eigen::Vector3d::UnitZ(), false), 0.995);
    data["ptm"] = {{"planes", uris}, {"lo", lo}, {"hi", hi}, {"exposure", exposure}};
  }
  if (!slices.empty()) {
    const int columns = int(std::ceil(std::sqrt(double(slices.size()))));
    auto atlas = PngDataUri(SliceAtlas(slices, tile, columns), PixelFormat::kUint8Srgb, scratch, "btf_atlas");
    if (!atlas.ok()) return atlas.status();
    Json list = Json::array();
    for (const ViewerSlice& s : slices)
      list.push_back({{"light", {s.light.x(), s.light.y(), s.light.z()}}, {"view", {s.view.x(), s.view.y(), s.view.z()}}});
    data["btf"] = {{"atlas", *atlas}, {"columns", columns},
                   {"rows", (int(slices.size()) + columns - 1) / columns}, {"slices", list}};
  }
  std::string html = "<section id=\"mesocap-viewer\"><p>Move the mouse over a picture to move the light (centre: "
                     "overhead). <span id=\"mesocap-viewer-light\"></span></p><div>";
  if (ptm) html += "<figure style=\"display:inline-block\"><canvas id=\"mesocap-viewer-ptm\" width=\"384\" height=\"384\"></canvas><figcaption>PTM of the top board</figcaption></figure>";
  if (!slices.empty())
    html += "<figure style=\"display:inline-block\"><canvas id=\"mesocap-viewer-btf\" width=\"384\" height=\"384\"></canvas><figcaption>Reconstructed BTF <select id=\"mesocap-viewer-view\"></select></figcaption></figure>";
  // The data: JSON in a script element (never executed); "</" cannot occur in it.
  std::string json = data.dump();
  for (size_t at; (at = json.find("</")) != std::string::npos;) json.replace(at, 2, "<\\/");
  html += "</div><script type=\"application/json\" id=\"mesocap-viewer-data\">" + json + "</script><script>" +
          kViewerScript + "</script></section>";
  return html;
}

}  // namespace mesocap
