// The llvmpipe yardstick: renders the triangles of an OBJ file with Mesa's OSMesa (the llvmpipe JIT
// rasterizer, GL 4.5 core where available) from the same camera and frame size as
// `roomrender bench-render`, reads the colour buffer back every frame, and prints one JSON line of
// frame times. A benchmark tool, not part of the service: it links nothing of roomrender.
// Conventions are roomrender's (docs/scene-format.md): world space, +Y up, glm::lookAt and
// glm::perspective, pixel (0, 0) top-left in the files it writes; --light-dir points toward the light.
// Faces are fan-triangulated (0, k+1, k+2) exactly as roomrender's rasterizer splits its polygons.
// --mode ambient draws each face in one flat colour (--face-colors: one "r g b" byte line per face,
// in f-line order) over --background, the matched setup of bench/antialias.py; --samples 4 renders
// into a 4x multisample framebuffer object and resolves it with glBlitFramebuffer every frame
// (OSMesa's own buffer has no multisample visual; an FBO in its context does).
// --mode textured draws each face in its material's Kd times its map_Kd image (the OBJ's `vt`, v up,
// `mtllib`/`usemtl`; nothing lit) with --textures nearest|bilinear|trilinear|anisotropic, the matched
// setup of bench/textured_peer.py. Textures are RGB8 (no sRGB decode) and repeat; a map named X_0.png
// takes its mip levels from X_1.png, X_2.png, ... when they exist (the chain roomrender built), else
// from glGenerateMipmap.
#define GL_GLEXT_PROTOTYPES 1
// osmesa.h first: it includes gl.h, which glext.h needs for GLenum and the rest.
#include <GL/osmesa.h>

#include <GL/glext.h>

#define GLM_FORCE_SILENT_WARNINGS
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// One vertex of the non-indexed triangle list: every triangle carries its face's normal (faceted,
// as roomrender's flat shading) and the 0-based index of its `f` line (the polygon id).
struct Vertex {
  float p[3];
  float n[3];
  uint32_t face;
  float c[3];   // --mode ambient: the face's colour, 0..1; --mode textured: its material's Kd
  float uv[2];  // --mode textured: the corner's vt (v up)
};

// A material of the OBJ's .mtl: Kd and the path of its map_Kd (empty: untextured).
struct ObjMaterial {
  std::string name, map;
  float kd[3] = {0.7f, 0.7f, 0.7f};
};

// Consecutive triangles of one material: one draw call of --mode textured.
struct DrawRun {
  GLint first = 0;
  GLsizei count = 0;
  size_t material = 0;
};

struct Mesh {
  std::vector<Vertex> vertices;  // 3 per triangle
  size_t faces = 0;
  glm::dvec3 lo{1e300}, hi{-1e300};
  std::vector<ObjMaterial> materials;  // from `mtllib`; [0] is the default when there is none
  std::vector<DrawRun> runs;
};

// Reads newmtl, Kd and map_Kd (paths relative to the .mtl) of an OBJ's material library.
void read_mtl(const std::string& path, std::vector<ObjMaterial>& out) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  const std::string dir = path.substr(0, path.find_last_of('/') + 1);
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "newmtl") s >> out.emplace_back().name;
    else if (key == "Kd" && !out.empty()) s >> out.back().kd[0] >> out.back().kd[1] >> out.back().kd[2];
    else if (key == "map_Kd" && !out.empty()) s >> out.back().map, out.back().map = dir + out.back().map;
  }
}

// Reads `v`, `vt`, `f`, `mtllib` and `usemtl` lines (f tokens may be i, i/t, i/t/n or i//n; negative
// indices count back from the last `v` or `vt`). Everything else is ignored.
Mesh read_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec2> uvs;
  std::vector<glm::dvec3> face;
  std::vector<glm::dvec2> face_uv;
  Mesh mesh;
  mesh.materials.emplace_back();
  size_t material = 0;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("mtllib ", 0) == 0) {
      mesh.materials.clear();
      read_mtl(path.substr(0, path.find_last_of('/') + 1) + line.substr(7), mesh.materials);
      if (mesh.materials.empty()) mesh.materials.emplace_back();
      continue;
    }
    if (line.rfind("usemtl ", 0) == 0) {
      auto it = std::find_if(mesh.materials.begin(), mesh.materials.end(),
                             [&](const ObjMaterial& m) { return m.name == line.substr(7); });
      if (it == mesh.materials.end()) throw std::runtime_error("unknown material " + line.substr(7));
      material = size_t(it - mesh.materials.begin());
      continue;
    }
    const bool vt = line.rfind("vt ", 0) == 0;
    if (!vt && (line.size() < 2 || line[1] != ' ' || (line[0] != 'v' && line[0] != 'f'))) continue;
    const char* s = line.c_str() + (vt ? 3 : 2);
    char* end = nullptr;
    if (vt) {
      glm::dvec2 uv;
      for (int k = 0; k < 2; ++k, s = end) uv[k] = std::strtod(s, &end);
      uvs.push_back(uv);
      continue;
    }
    if (line[0] == 'v') {
      glm::dvec3 p;
      for (int k = 0; k < 3; ++k, s = end) p[k] = std::strtod(s, &end);
      positions.push_back(p);
      continue;
    }
    face.clear();
    face_uv.clear();
    for (;;) {
      long index = std::strtol(s, &end, 10);
      if (end == s) break;
      long i = index < 0 ? long(positions.size()) + index : index - 1;
      if (i < 0 || size_t(i) >= positions.size()) throw std::runtime_error("bad face index in " + path);
      face.push_back(positions[size_t(i)]);
      glm::dvec2 uv(0.0);
      if (*end == '/' && end[1] != '/') {
        s = end + 1;
        long t = std::strtol(s, &end, 10);
        long j = t < 0 ? long(uvs.size()) + t : t - 1;
        if (j < 0 || size_t(j) >= uvs.size()) throw std::runtime_error("bad texture index in " + path);
        uv = uvs[size_t(j)];
      }
      face_uv.push_back(uv);
      for (s = end; *s && *s != ' ' && *s != '\t'; ++s) {
      }  // skip /n
    }
    if (face.size() < 3) throw std::runtime_error("face with fewer than 3 vertices in " + path);
    glm::dvec3 newell(0.0);  // twice the vector area; robust for any planar polygon
    for (size_t k = 0; k < face.size(); ++k) newell += glm::cross(face[k], face[(k + 1) % face.size()]);
    double len = glm::length(newell);
    glm::vec3 n = len > 0.0 ? glm::vec3(newell / len) : glm::vec3(0, 1, 0);
    const float* kd = mesh.materials[material].kd;
    auto emit = [&](size_t k) {
      const glm::dvec3& p = face[k];
      mesh.vertices.push_back({{float(p.x), float(p.y), float(p.z)},
                               {n.x, n.y, n.z},
                               uint32_t(mesh.faces),
                               {kd[0], kd[1], kd[2]},
                               {float(face_uv[k].x), float(face_uv[k].y)}});
      mesh.lo = glm::min(mesh.lo, p);
      mesh.hi = glm::max(mesh.hi, p);
    };
    if (mesh.runs.empty() || mesh.runs.back().material != material) {
      mesh.runs.push_back({GLint(mesh.vertices.size()), 0, material});
    }
    for (size_t k = 0; k + 2 < face.size(); ++k) {
      emit(0), emit(k + 1), emit(k + 2);
    }
    mesh.runs.back().count = GLsizei(mesh.vertices.size()) - mesh.runs.back().first;
    ++mesh.faces;
  }
  return mesh;
}

struct Options {
  std::string obj, mode = "lambert", out, ids, face_colors, textures = "trilinear";
  glm::dvec3 eye{0, 1.6, 5}, target{0, 1, 0}, up{0, 1, 0}, light_dir{0, 1, 0}, background{0, 0, 0};
  double fovy = 60, near = 0.1, far = 100;
  int width = 1280, height = 720, frames = 10, warmup = 1, shadow_size = 2048, samples = 1;
};

// --face-colors: "r g b" (0..255) per face, in the OBJ's f-line order, onto every vertex of the face.
void apply_face_colors(Mesh& mesh, const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<glm::vec3> colors;
  for (int r, g, b; in >> r >> g >> b;) colors.push_back(glm::vec3(float(r), float(g), float(b)) / 255.0f);
  if (colors.size() != mesh.faces) {
    throw std::runtime_error(path + " has " + std::to_string(colors.size()) + " colours for " +
                             std::to_string(mesh.faces) + " faces");
  }
  for (Vertex& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) v.c[k] = colors[v.face][k];
  }
}

glm::dvec3 parse_vec3(const std::string& text) {
  glm::dvec3 v;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf", &v.x, &v.y, &v.z) != 3) {
    throw std::runtime_error("expected x,y,z, not '" + text + "'");
  }
  return v;
}

Options parse_options(int argc, char** argv) {
  std::map<std::string, std::string> flags;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0 || i + 1 == argc) throw std::runtime_error("expected --flag VALUE at " + arg);
    flags[arg] = argv[++i];
  }
  Options o;
  for (const auto& [name, value] : flags) {
    if (name == "--obj") o.obj = value;
    else if (name == "--mode") o.mode = value;
    else if (name == "--out") o.out = value;
    else if (name == "--ids") o.ids = value;
    else if (name == "--eye") o.eye = parse_vec3(value);
    else if (name == "--target") o.target = parse_vec3(value);
    else if (name == "--up") o.up = parse_vec3(value);
    else if (name == "--light-dir") o.light_dir = parse_vec3(value);
    else if (name == "--fovy") o.fovy = std::stod(value);
    else if (name == "--near") o.near = std::stod(value);
    else if (name == "--far") o.far = std::stod(value);
    else if (name == "--frames") o.frames = std::stoi(value);
    else if (name == "--warmup") o.warmup = std::stoi(value);
    else if (name == "--shadow-size") o.shadow_size = std::stoi(value);
    else if (name == "--samples") o.samples = std::stoi(value);
    else if (name == "--face-colors") o.face_colors = value;
    else if (name == "--textures") o.textures = value;
    else if (name == "--background") o.background = parse_vec3(value) / 255.0;
    else if (name == "--size") {
      if (std::sscanf(value.c_str(), "%dx%d", &o.width, &o.height) != 2) throw std::runtime_error("--size WxH");
    } else {
      throw std::runtime_error("unknown flag " + name);
    }
  }
  if (o.obj.empty()) throw std::runtime_error("--obj FILE is required");
  if (o.mode != "lambert" && o.mode != "phong_shadow" && o.mode != "ambient" && o.mode != "textured") {
    throw std::runtime_error("--mode lambert|phong_shadow|ambient|textured");
  }
  if (o.textures != "nearest" && o.textures != "bilinear" && o.textures != "trilinear" && o.textures != "anisotropic") {
    throw std::runtime_error("--textures nearest|bilinear|trilinear|anisotropic");
  }
  if (o.mode == "ambient" && o.face_colors.empty()) throw std::runtime_error("--mode ambient needs --face-colors");
  if (o.samples != 1 && o.samples != 4) throw std::runtime_error("--samples 1|4");
  if (o.frames < 1 || o.width < 1 || o.height < 1) throw std::runtime_error("--frames and --size must be positive");
  return o;
}

// Shaders. The colour passes light one directional light plus ambient 0.2 on a grey surface; open
// surfaces are lit on the side facing the eye (gl_FrontFacing), as roomrender lights them.
constexpr const char* vertex_shader = R"(#version 330 core
layout(location = 0) in vec3 p_world;
layout(location = 1) in vec3 normal;
layout(location = 2) in uint face;
layout(location = 3) in vec3 face_color;
layout(location = 4) in vec2 uv;
uniform mat4 clip_from_world;
uniform mat4 light_clip_from_world;
out vec3 v_normal;
out vec3 v_world;
out vec4 v_light_clip;
flat out uint v_face;
flat out vec3 v_color;
out vec2 v_uv;
void main() {
  v_color = face_color;
  v_uv = uv;
  v_normal = normal;
  v_world = p_world;
  v_light_clip = light_clip_from_world * vec4(p_world, 1.0);
  v_face = face;
  gl_Position = clip_from_world * vec4(p_world, 1.0);
})";

constexpr const char* lambert_fragment = R"(#version 330 core
in vec3 v_normal; in vec3 v_world; in vec4 v_light_clip; flat in uint v_face;
uniform vec3 to_light;
out vec4 color;
void main() {
  vec3 n = gl_FrontFacing ? v_normal : -v_normal;
  float diffuse = max(dot(n, to_light), 0.0);
  color = vec4(vec3(0.7) * (0.2 + diffuse), 1.0);
})";

// The matched setup of the anti-aliasing bench: the face's own colour, nothing lit.
constexpr const char* ambient_fragment = R"(#version 330 core
flat in vec3 v_color;
out vec4 color;
void main() { color = vec4(v_color, 1.0); }
)";

// The matched setup of the texture bench: Kd times the filtered texel, nothing lit.
constexpr const char* textured_fragment = R"(#version 330 core
flat in vec3 v_color;
in vec2 v_uv;
uniform sampler2D albedo;
uniform bool textured;
out vec4 color;
void main() { color = vec4(v_color * (textured ? texture(albedo, v_uv).rgb : vec3(1.0)), 1.0); }
)";

// Blinn-Phong with a hard (PCF 1: one nearest-texel compare) shadow-map lookup.
constexpr const char* phong_fragment = R"(#version 330 core
in vec3 v_normal; in vec3 v_world; in vec4 v_light_clip; flat in uint v_face;
uniform vec3 to_light;
uniform vec3 eye;
uniform sampler2DShadow shadow_map;
out vec4 color;
void main() {
  vec3 n = normalize(gl_FrontFacing ? v_normal : -v_normal);
  vec3 to_eye = normalize(eye - v_world);
  vec3 shadow_p = v_light_clip.xyz / v_light_clip.w * 0.5 + 0.5;
  float lit = texture(shadow_map, shadow_p);
  float diffuse = max(dot(n, to_light), 0.0);
  float specular = diffuse > 0.0 ? pow(max(dot(n, normalize(to_light + to_eye)), 0.0), 32.0) : 0.0;
  color = vec4(vec3(0.7) * (0.2 + lit * diffuse) + vec3(0.3) * lit * specular, 1.0);
})";

// The light's depth pass transforms positions only: a real renderer's shadow pass is this lean.
constexpr const char* depth_vertex_shader = R"(#version 330 core
layout(location = 0) in vec3 p_world;
uniform mat4 clip_from_world;
void main() { gl_Position = clip_from_world * vec4(p_world, 1.0); })";

constexpr const char* depth_fragment = R"(#version 330 core
void main() {}
)";

constexpr const char* id_fragment = R"(#version 330 core
in vec3 v_normal; in vec3 v_world; in vec4 v_light_clip; flat in uint v_face;
out uint id;
void main() { id = v_face; }
)";

GLuint compile(GLenum type, const char* source) {
  GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("shader: ") + log);
  }
  return shader;
}

GLuint link(const char* fragment_source, const char* vertex_source = vertex_shader) {
  GLuint program = glCreateProgram();
  glAttachShader(program, compile(GL_VERTEX_SHADER, vertex_source));
  glAttachShader(program, compile(GL_FRAGMENT_SHADER, fragment_source));
  glLinkProgram(program);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("program link failed");
  return program;
}

void set_mat4(GLuint program, const char* name, const glm::dmat4& m) {
  glm::mat4 f(m);
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, glm::value_ptr(f));
}

void set_vec3(GLuint program, const char* name, const glm::dvec3& v) {
  glUniform3f(glGetUniformLocation(program, name), float(v.x), float(v.y), float(v.z));
}

// A depth texture the light renders into, sampled with hardware comparison at the nearest texel.
struct ShadowTarget {
  GLuint texture = 0, framebuffer = 0;
};

ShadowTarget make_shadow_target(int size) {
  ShadowTarget t;
  glGenTextures(1, &t.texture);
  glBindTexture(GL_TEXTURE_2D, t.texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, size, size, 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glGenFramebuffers(1, &t.framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, t.framebuffer);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, t.texture, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error("shadow framebuffer incomplete");
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return t;
}

// An orthographic light camera looking along -to_light that encloses the scene's bounding sphere.
glm::dmat4 fit_light(const Mesh& mesh, glm::dvec3 to_light) {
  glm::dvec3 centre = 0.5 * (mesh.lo + mesh.hi);
  double r = std::max(0.5 * glm::length(mesh.hi - mesh.lo), 1e-6);
  glm::dvec3 up = std::abs(to_light.y) > 0.99 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  glm::dmat4 view = glm::lookAt(centre + to_light * (2.0 * r), centre, up);
  return glm::ortho(-r, r, -r, r, r, 3.0 * r) * view;
}

// An image as RGB8 rows from the bottom, GL's order, so that t is the OBJ's v (v up).
std::vector<uint8_t> read_rgb_bottom_up(const std::string& path, int& w, int& h) {
  int channels = 0;
  uint8_t* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
  if (!data) throw std::runtime_error("cannot read image " + path);
  std::vector<uint8_t> rgb(size_t(w) * size_t(h) * 3);
  for (int y = 0; y < h; ++y)
    std::memcpy(&rgb[size_t(h - 1 - y) * size_t(w) * 3], data + size_t(y) * size_t(w) * 3, size_t(w) * 3);
  stbi_image_free(data);
  return rgb;
}

// A map_Kd texture: repeat in both directions, the filter of --textures. Its mip levels are the files
// X_1.png, X_2.png, ... beside X_0.png (each side halved, rounding down, to 1 x 1: a complete chain),
// else glGenerateMipmap's. Anisotropic is trilinear with GL_TEXTURE_MAX_ANISOTROPY at `anisotropy`.
struct MapTexture {
  GLuint name = 0;
  int levels = 1;
  bool generated = false;  // the chain is glGenerateMipmap's, not the files'
};

MapTexture make_map_texture(const std::string& path, const std::string& filter, float anisotropy) {
  MapTexture t;
  glGenTextures(1, &t.name);
  glBindTexture(GL_TEXTURE_2D, t.name);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  int w = 0, h = 0;
  std::vector<uint8_t> rgb = read_rgb_bottom_up(path, w, h);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, w, h, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  const bool mipmapped = filter == "trilinear" || filter == "anisotropic";
  const std::string suffix = "_0.png";
  if (mipmapped && path.size() > suffix.size() &&
      path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0) {
    const std::string stem = path.substr(0, path.size() - suffix.size());
    for (;; ++t.levels) {
      const std::string next = stem + "_" + std::to_string(t.levels) + ".png";
      if (!std::ifstream(next)) break;
      int lw = 0, lh = 0;
      rgb = read_rgb_bottom_up(next, lw, lh);
      if (lw != std::max(1, w >> t.levels) || lh != std::max(1, h >> t.levels)) {
        throw std::runtime_error(next + " is not half the size of the level above");
      }
      glTexImage2D(GL_TEXTURE_2D, t.levels, GL_RGB8, lw, lh, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    }
  }
  if (mipmapped && t.levels == 1 && (w > 1 || h > 1)) {
    glGenerateMipmap(GL_TEXTURE_2D);
    t.generated = true;
    for (int s = std::max(w, h); s > 1; s /= 2) ++t.levels;
  }
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, t.levels - 1);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter == "nearest" ? GL_NEAREST : GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                  filter == "nearest"    ? GL_NEAREST
                  : filter == "bilinear" ? GL_LINEAR
                                         : GL_LINEAR_MIPMAP_LINEAR);
  if (filter == "anisotropic") glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MAX_ANISOTROPY_EXT, anisotropy);
  return t;
}

// PNG via stb_image_write (the harness is its own program, so it holds its own implementation).
void write_png(const std::string& path, const std::vector<uint8_t>& rgba, int w, int h) {
  stbi_flip_vertically_on_write(1);  // GL rows run bottom-up
  if (!stbi_write_png(path.c_str(), w, h, 4, rgba.data(), w * 4)) throw std::runtime_error("cannot write " + path);
}

// roomrender's id-buffer format: uint32 width, height, then ids row-major from the top-left.
void write_ids(const std::string& path, const std::vector<uint32_t>& ids, int w, int h) {
  std::ofstream out(path, std::ios::binary);
  uint32_t header[2] = {uint32_t(w), uint32_t(h)};
  out.write(reinterpret_cast<const char*>(header), sizeof header);
  for (int y = h - 1; y >= 0; --y) {
    out.write(reinterpret_cast<const char*>(&ids[size_t(y) * w]), std::streamsize(sizeof(uint32_t)) * w);
  }
  if (!out) throw std::runtime_error("cannot write " + path);
}

// Renders the polygon ids once, outside the timed loop, into an integer colour attachment.
std::vector<uint32_t> render_ids(GLsizei vertex_count, const glm::dmat4& clip_from_world, int w, int h) {
  GLuint color = 0, depth = 0, fb = 0;
  glGenRenderbuffers(1, &color);
  glBindRenderbuffer(GL_RENDERBUFFER, color);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_R32UI, w, h);
  glGenRenderbuffers(1, &depth);
  glBindRenderbuffer(GL_RENDERBUFFER, depth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
  glGenFramebuffers(1, &fb);
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error("id framebuffer incomplete");
  }
  GLuint program = link(id_fragment);
  glUseProgram(program);
  set_mat4(program, "clip_from_world", clip_from_world);
  set_mat4(program, "light_clip_from_world", glm::dmat4(1.0));
  const GLuint background[4] = {0xFFFFFFFFu, 0, 0, 0};
  glClearBufferuiv(GL_COLOR, 0, background);
  glClear(GL_DEPTH_BUFFER_BIT);
  glDrawArrays(GL_TRIANGLES, 0, vertex_count);
  std::vector<uint32_t> ids(size_t(w) * size_t(h));
  glReadPixels(0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_INT, ids.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return ids;
}

// The --samples 4 target: colour and depth renderbuffers of `samples` samples, resolved by a blit
// into a single-sample colour renderbuffer that glReadPixels reads.
struct MsaaTarget {
  GLuint draw = 0, resolve = 0;
  GLint samples = 1;
};

MsaaTarget make_msaa_target(int samples, int w, int h) {
  GLint max_samples = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (samples > max_samples) throw std::runtime_error("GL_MAX_SAMPLES is " + std::to_string(max_samples));
  GLuint buffers[3] = {};
  glGenRenderbuffers(3, buffers);
  glBindRenderbuffer(GL_RENDERBUFFER, buffers[0]);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, w, h);
  glBindRenderbuffer(GL_RENDERBUFFER, buffers[1]);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, w, h);
  glBindRenderbuffer(GL_RENDERBUFFER, buffers[2]);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  MsaaTarget t;
  glGenFramebuffers(1, &t.draw);
  glBindFramebuffer(GL_FRAMEBUFFER, t.draw);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, buffers[0]);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, buffers[1]);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("MSAA framebuffer incomplete");
  glGetIntegerv(GL_SAMPLES, &t.samples);  // what the driver allocated (it may round the request up)
  if (t.samples != samples)
    throw std::runtime_error("asked for " + std::to_string(samples) + " samples, got " + std::to_string(t.samples));
  glGenFramebuffers(1, &t.resolve);
  glBindFramebuffer(GL_FRAMEBUFFER, t.resolve);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, buffers[2]);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("resolve framebuffer incomplete");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return t;
}

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int run(const Options& o) {
  if (!std::getenv("GALLIUM_DRIVER")) setenv("GALLIUM_DRIVER", "llvmpipe", 1);
  Mesh mesh = read_obj(o.obj);
  if (!o.face_colors.empty()) apply_face_colors(mesh, o.face_colors);
  const double setup_start = now_ms();
  // Ask for GL 4.5 core; OSMesa returns a context of at least that version or null, so fall back
  // to 3.3 core, which has everything the shaders use.
  OSMesaContext context = nullptr;
  for (int minor_major : {45, 33}) {
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           minor_major / 10,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           minor_major % 10,
                           0};
    if ((context = OSMesaCreateContextAttribs(attribs, nullptr))) break;
  }
  if (!context) throw std::runtime_error("OSMesaCreateContextAttribs failed");
  std::vector<uint8_t> window(size_t(o.width) * size_t(o.height) * 4);  // OSMesa's default framebuffer
  if (!OSMesaMakeCurrent(context, window.data(), GL_UNSIGNED_BYTE, o.width, o.height)) {
    throw std::runtime_error("OSMesaMakeCurrent failed");
  }
  const bool shadowed = o.mode == "phong_shadow";
  GLuint vao = 0, vbo = 0;
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glGenBuffers(1, &vbo);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.vertices.size() * sizeof(Vertex)), mesh.vertices.data(),
               GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, p)));
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, n)));
  glVertexAttribIPointer(2, 1, GL_UNSIGNED_INT, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, face)));
  glVertexAttribPointer(3, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, c)));
  glVertexAttribPointer(4, 2, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, uv)));
  for (GLuint a = 0; a < 5; ++a) glEnableVertexAttribArray(a);
  const GLsizei vertex_count = GLsizei(mesh.vertices.size());

  const glm::dvec3 to_light = glm::normalize(o.light_dir);
  const glm::dmat4 clip_from_world = glm::perspective(glm::radians(o.fovy), double(o.width) / o.height, o.near, o.far) *
                                     glm::lookAt(o.eye, o.target, o.up);
  const glm::dmat4 light_clip = fit_light(mesh, to_light);
  const bool textured = o.mode == "textured";
  GLuint color_program = link(shadowed              ? phong_fragment
                              : o.mode == "ambient" ? ambient_fragment
                              : textured            ? textured_fragment
                                                    : lambert_fragment);
  glUseProgram(color_program);
  set_mat4(color_program, "clip_from_world", clip_from_world);
  set_mat4(color_program, "light_clip_from_world", light_clip);
  set_vec3(color_program, "to_light", to_light);
  if (shadowed) set_vec3(color_program, "eye", o.eye);
  GLuint depth_program = 0;
  ShadowTarget shadow;
  if (shadowed) {
    glUniform1i(glGetUniformLocation(color_program, "shadow_map"), 0);
    shadow = make_shadow_target(o.shadow_size);
    depth_program = link(depth_fragment, depth_vertex_shader);
    glUseProgram(depth_program);
    set_mat4(depth_program, "clip_from_world", light_clip);
  }
  // Our anisotropic filter takes at most 16 taps: ask for 16, or the driver's maximum when lower.
  GLfloat max_anisotropy = 0.0f;
  glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT, &max_anisotropy);
  const float anisotropy = std::min(16.0f, max_anisotropy);
  std::vector<MapTexture> maps(mesh.materials.size());
  int generated_chains = 0;
  if (textured) {
    glUseProgram(color_program);
    glUniform1i(glGetUniformLocation(color_program, "albedo"), 0);
    for (size_t k = 0; k < maps.size(); ++k) {
      if (mesh.materials[k].map.empty()) continue;
      maps[k] = make_map_texture(mesh.materials[k].map, o.textures, anisotropy);
      generated_chains += maps[k].generated;
    }
  }
  const GLint textured_uniform = glGetUniformLocation(color_program, "textured");
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);  // ties keep the first drawn, as roomrender's z-buffer
  glClearColor(float(o.background.r), float(o.background.g), float(o.background.b), 1.0f);
  const MsaaTarget msaa = o.samples > 1 ? make_msaa_target(o.samples, o.width, o.height) : MsaaTarget{};
  glFinish();
  const double setup_ms = now_ms() - setup_start;

  std::vector<uint8_t> readback(size_t(o.width) * size_t(o.height) * 4);
  auto frame = [&] {
    if (shadowed) {
      glBindFramebuffer(GL_FRAMEBUFFER, shadow.framebuffer);
      glViewport(0, 0, o.shadow_size, o.shadow_size);
      glClear(GL_DEPTH_BUFFER_BIT);
      glUseProgram(depth_program);
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(2.0f, 4.0f);  // slope-scaled + constant bias against self-shadowing acne
      glDrawArrays(GL_TRIANGLES, 0, vertex_count);
      glDisable(GL_POLYGON_OFFSET_FILL);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, shadow.texture);
    }
    glViewport(0, 0, o.width, o.height);
    glUseProgram(color_program);
    glBindFramebuffer(GL_FRAMEBUFFER, msaa.draw);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (textured) {  // one draw per run of a material, in f-line order (depth ties keep the first)
      glActiveTexture(GL_TEXTURE0);
      for (const DrawRun& run : mesh.runs) {
        const GLuint map = maps[run.material].name;
        glUniform1i(textured_uniform, map != 0);
        if (map) glBindTexture(GL_TEXTURE_2D, map);
        glDrawArrays(GL_TRIANGLES, run.first, run.count);
      }
    } else {
      glDrawArrays(GL_TRIANGLES, 0, vertex_count);
    }
    if (msaa.draw) {
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, msaa.resolve);
      glBlitFramebuffer(0, 0, o.width, o.height, 0, 0, o.width, o.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa.resolve);
    }
    glReadPixels(0, 0, o.width, o.height, GL_RGBA, GL_UNSIGNED_BYTE, readback.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glFinish();
  };
  for (int i = 0; i < o.warmup; ++i) frame();  // the first draw JIT-compiles shader variants
  std::vector<double> times;
  for (int i = 0; i < o.frames; ++i) {
    double t0 = now_ms();
    frame();
    times.push_back(now_ms() - t0);
  }
  if (GLenum error = glGetError(); error != GL_NO_ERROR) throw std::runtime_error("GL error " + std::to_string(error));
  if (!o.out.empty()) write_png(o.out, readback, o.width, o.height);
  if (!o.ids.empty()) write_ids(o.ids, render_ids(vertex_count, clip_from_world, o.width, o.height), o.width, o.height);

  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  const size_t n = sorted.size();  // the median of an even count is the mean of the middle two
  const double median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  const char* threads = std::getenv("LP_NUM_THREADS");
  std::printf(
      "{\"peer\":\"osmesa\",\"renderer\":\"%s\",\"gl_version\":\"%s\",\"lp_num_threads\":\"%s\","
      "\"mode\":\"%s\",\"textures\":\"%s\",\"max_anisotropy\":%g,\"generated_mip_chains\":%d,\"samples\":%d,\"faces\":%"
      "zu,\"triangles\":%zu,\"width\":%d,\"height\":%d,\"shadow_size\":%d,"
      "\"frames\":%d,\"warmup\":%d,\"setup_ms\":%.3f,\"frame_ms_min\":%.3f,\"frame_ms_median\":%.3f,"
      "\"frame_ms_max\":%.3f}\n",
      reinterpret_cast<const char*>(glGetString(GL_RENDERER)), reinterpret_cast<const char*>(glGetString(GL_VERSION)),
      threads ? threads : "default", o.mode.c_str(), textured ? o.textures.c_str() : "none",
      textured && o.textures == "anisotropic" ? double(anisotropy) : 0.0, generated_chains, o.samples, mesh.faces,
      mesh.vertices.size() / 3, o.width, o.height, shadowed ? o.shadow_size : 0, o.frames, o.warmup, setup_ms,
      sorted.front(), median, sorted.back());
  OSMesaDestroyContext(context);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse_options(argc, argv));
  } catch (const std::exception& e) {
    std::string message = e.what();  // shader logs may hold quotes and newlines: keep the line valid JSON
    for (char& c : message) c = (c == '"' || c == '\\' || c == '\n') ? ' ' : c;
    std::fprintf(stderr, "{\"error\":\"%s\"}\n", message.c_str());
    return 1;
  }
}
