// Plain structs for a parsed render request (docs/scene-format.md), with every default applied.
// World space: metres, right-handed, +Y up; plan points are (x, z). Produced by scene_json, consumed
// by tessellate (static geometry) and the pipelines (camera, lights, options). No behaviour here.
#pragma once

#include "render/core/math.hpp"
#include "render/core/mesh_data.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rr {

struct MaterialParams {
  float specular = 0.0f;  // Blinn-Phong specular strength, 0..1
  Color specular_color{1.0f, 1.0f, 1.0f};
  float shininess = 32.0f;  // Blinn-Phong exponent
  friend bool operator==(const MaterialParams&, const MaterialParams&) = default;
};

struct TextureImage;  // texture.hpp

// An image on a surface. Floors, rooms, wall sides and solids (other than meshes with texture
// coordinates) place it by a planar mapping: tiles of width x height metres, shifted by the offsets (in
// tiles) and turned by `angle` (docs/scene-format.md says along which axes, per surface). A surface's
// colour multiplies the texel (a textured surface's colour defaults to white).
struct SurfaceTexture {
  std::string image;                            // as the request named it: a data: URI or a stored id
  std::shared_ptr<const TextureImage> decoded;  // never null once read
  double width = 1.0, height = 1.0;             // one tile, metres
  double x_offset = 0.0, y_offset = 0.0;        // fractions of a tile
  double angle = 0.0;                           // radians, counter-clockwise seen from the front
};

struct Floor {
  std::string id;
  Vec2 origin{0.0, 0.0};  // (x, z) of the corner of cell (0, 0): its minimum x and z
  int cells_x = 1;
  int cells_z = 1;
  double cell_size = 1.0;
  double elevation = 0.0;
  std::vector<Color> colors;  // >= 2; cell (i, j) takes colors[(i + j) % n]
  MaterialParams material;
  std::shared_ptr<const SurfaceTexture> texture;  // null: untextured; else over every cell
  int level = -1;                                 // index into StaticGeometry::levels, -1: on no level (always drawn)
};

enum class OpeningType { door, window };

struct Opening {
  OpeningType type = OpeningType::door;
  std::string id;
  double offset = 0.0;  // along the centreline from the wall's start to the near edge
  double width = 0.9;
  double height = 2.0;
  double sill = 0.0;  // above the wall's base; 0 for doors
  Color color{0.545f, 0.353f, 0.169f};
  float opacity = 1.0f;  // windows only
  bool leaf = true;      // doors only: a leaf closes the opening
};

struct Wall {
  std::string id;
  Vec2 start{0.0, 0.0};
  Vec2 end{1.0, 0.0};
  double thickness = 0.15;
  double height = 2.5;
  double base = 0.0;
  Color color{0.902f, 0.882f, 0.839f};
  MaterialParams material;
  // Its two long sides, seen walking from start to end in the plan (x right, z down, as Sweet Home 3D
  // draws it): the left side faces (dz, -dx) for a direction (dx, dz), the right side the opposite.
  // A side without a colour of its own takes `color`; reveals, end caps and the top keep `color`,
  // untextured.
  std::optional<Color> left_color, right_color;
  std::shared_ptr<const SurfaceTexture> left_texture, right_texture;  // null: untextured
  std::vector<Opening> openings;
  int level = -1;
};

enum class SolidType { box, cylinder, pyramid, prism, mesh, piece };

// One part of a piece: a mesh (inline or stored) with its own colour and material, placed in the
// piece's unit box [-0.5, 0.5]^3 by `transform` (identity when `transformed` is false).
struct PiecePart {
  std::string name;                      // labels the part (a pick names it); draws nothing
  std::shared_ptr<const MeshData> mesh;  // never null once read
  std::string mesh_ref;                  // the stored mesh's id when placed by "ref"; empty when inline
  Color color{0.7f, 0.7f, 0.7f};
  MaterialParams material;
  std::shared_ptr<const SurfaceTexture> texture;  // null: untextured; by the mesh's uvs when it has them
  bool transformed = false;
  Mat3 linear{1.0};  // unit-box point = linear * mesh point + offset
  Vec3 offset{0.0};
};

struct Solid {
  SolidType type = SolidType::box;
  std::string id;
  Color color{0.7f, 0.7f, 0.7f};
  MaterialParams material;
  std::shared_ptr<const SurfaceTexture> texture;  // null: untextured; a mesh with uvs uses them
  // Footprint solids (box, cylinder, pyramid, piece).
  Vec2 center{0.0, 0.0};
  double base = 0.0;
  double rotation_y_deg = 0.0;  // counter-clockwise seen from above
  Vec3 size{1.0, 1.0, 1.0};     // box, pyramid and piece: (sx, height, sz)
  // Cylinder.
  double radius = 0.5;
  double height = 1.0;  // cylinder and prism
  int segments = 32;
  bool smooth = true;  // cylinder default true, mesh default false (set by the parser)
  bool caps = true;
  // Prism.
  std::vector<Vec2> points;  // simple polygon in the plan
  // Mesh: shared object-space geometry (inline or stored), placed by scale, then rotation_y, then
  // position. Never null for a mesh; null for the other types.
  std::shared_ptr<const MeshData> mesh;
  std::string mesh_ref;  // the stored mesh's id when placed by "ref"; empty when inline
  Vec3 position{0.0, 0.0, 0.0};
  Vec3 scale{1.0, 1.0, 1.0};
  bool closed = false;  // mesh only; the other solids know whether they are closed
  // Piece: its parts fill the unit box, which is stretched to `size` (mirrored across its width axis
  // when `mirrored`), turned by rotation_y and stood on (center, base), as a box is placed.
  std::vector<PiecePart> parts = {};
  bool mirrored = false;
  int level = -1;
};

// A storey: elements tagged with it are drawn when the request selects it (RenderOptions::levels).
struct Level {
  std::string id;
  double elevation = 0.0;  // its floor's y
  double height = 2.5;     // floor to ceiling: the default ceiling height of its rooms
  bool viewable = true;    // drawn when the request names no levels
};

// A room: a floor polygon facing up and, unless `ceiling` is false, the same polygon facing down at
// elevation + ceiling_height. The parser resolves every default (level elevation and height).
struct Room {
  std::string id;
  std::vector<Vec2> points;  // simple polygon in the plan (x, z), either winding
  double elevation = 0.0;
  bool floor = true;
  Color floor_color{0.851f, 0.831f, 0.780f};
  MaterialParams floor_material;
  std::shared_ptr<const SurfaceTexture> floor_texture;  // null: untextured
  bool ceiling = true;
  double ceiling_height = 2.5;
  Color ceiling_color{0.941f, 0.941f, 0.941f};
  std::shared_ptr<const SurfaceTexture> ceiling_texture;  // null: untextured
  int level = -1;
};

enum class LightType { directional, point };

struct Light {
  LightType type = LightType::directional;
  std::string id;
  Vec3 direction{0.0, -1.0, 0.0};  // directional: the direction the light travels (unit length)
  Vec3 position{0.0, 2.0, 0.0};    // point
  Color color{1.0f, 1.0f, 1.0f};
  float intensity = 1.0f;
  Vec3 attenuation{1.0, 0.0, 0.0};  // point: 1 / (c + l*d + q*d^2)
};

struct Ambient {
  Color color{1.0f, 1.0f, 1.0f};
  float intensity = 0.2f;
};

// Everything the tessellator reads. Its canonical hash is the scene id.
struct StaticGeometry {
  bool has_floor = false;
  Floor floor;
  std::vector<Wall> walls;
  std::vector<Solid> solids;
  std::vector<Room> rooms;
  std::vector<Level> levels;
};

struct Scene {
  StaticGeometry geometry;
  Color background{0.0f, 0.0f, 0.0f};
  Ambient ambient;
  std::vector<Light> lights;
};

struct Camera {
  Vec3 position{0.0, 1.6, 5.0};
  Vec3 target{0.0, 1.0, 0.0};
  Vec3 up{0.0, 1.0, 0.0};
  double fov_y_deg = 60.0;
  double near = 0.1;
  double far = 100.0;
  // "frame": "all": position and target are chosen to frame the scene (frame_bounds in camera.hpp)
  // once its bounds are known; up, fov_y, near and far still apply.
  bool frame_all = false;
};

// A row of the pipeline table (render/pipelines/pipeline_table.cpp), which sits above this floor:
// the default, row 0, is zbuffer. An index rather than an enum so that adding a pipeline is a row
// there and no edit here; code that names a pipeline looks it up (pipeline_id("bsp")).
struct PipelineId {
  std::uint8_t index = 0;
  friend constexpr bool operator==(PipelineId, PipelineId) = default;
};

// Every enum below has a name table in scene_names.hpp.
enum class ShadingMode { flat, gouraud, phong };

// Painter's sort key: mean / min (nearest vertex) / max view depth, or newell (mean order refined by
// the Newell-Newell-Sancha tests, splitting polygons to break cycles).
enum class PainterKey { mean, min, max, newell };

// PNG encoder (png.hpp): fast (parallel zlib strips), small (stb_image_write, the reference), none.
enum class PngCompression { fast, small, none };

// BSP walk (bsp.hpp): front to back with a coverage buffer that skips hidden subtrees (default), or
// the classic back-to-front walk. Both give the same image; the option exists to compare them.
enum class BspTraversal { front_to_back, back_to_front };

// What a directional shadow map is fitted to (docs/lighting.md): the receivers the camera sees
// (sharpest; reused only for the same view) or every receiver of the scene (reused by every camera).
enum class ShadowFit { view, scene };

// How a visible point's shadow from each light is decided (docs/lighting.md): shadow maps (the
// shadow pass, filtered lookups) or one exact ray toward the light per point and light, through the
// static scene's shadow-ray tree (shadow_rays.hpp), as the reference decides it.
enum class ShadowMethod { map, rays };

struct BspOptions {
  // Splitter score w1*|front - back| + w2*splits + w3*coplanar (lower is better).
  double w1 = 1.0;
  double w2 = 4.0;
  double w3 = -1.0;
  // Classification band as a fraction of the scene's bounding-box diagonal (docs/scene-format.md).
  double epsilon = 1e-7;
  int max_candidates = 32;  // splitter candidates scored per node when the node holds more polygons
  BspTraversal traversal = BspTraversal::front_to_back;  // not part of the tree's cache key
};

struct ShadowOptions {
  int size = 2048;          // shadow map side in texels (per cube face for point lights), 64..4096
  int pcf = 1;              // percentage-closer filter kernel: 1 (hard), 3 or 5
  double bias = 0.0;        // extra constant depth bias in texels of depth, added to the default
  double slope_bias = 0.0;  // extra slope-scaled bias, added to the default
  ShadowFit fit = ShadowFit::view;
  ShadowMethod method = ShadowMethod::map;  // rays: size, pcf, biases and fit are not read
};

// Which ceilings a view draws: auto draws a room's ceiling when the camera is below it (an aerial
// view sees into the rooms), on draws every ceiling, off none.
enum class CeilingMode { automatic, on, off };

// Whether a frame skips what is hidden behind what it has drawn (docs/culling.md). It changes the
// time only: the pipelines that use it give the same bytes either way; off is the check of that.
enum class CullingMode { on, off };

// options.exposure: a multiplier in (0, max_exposure]; "auto" picks one in [min_auto_exposure,
// max_auto_exposure] so the frame's mean luminance is auto_exposure_target (render.cpp).
inline constexpr double max_exposure = 64.0;
inline constexpr double min_auto_exposure = 1.0 / 16.0;
inline constexpr double max_auto_exposure = 16.0;
inline constexpr double auto_exposure_target = 0.45;

// How textured surfaces are filtered (texture.hpp, sample_texture).
enum class TextureFilter { nearest, bilinear, trilinear, anisotropic };

struct RenderOptions {
  int width = 640;
  int height = 480;
  PipelineId pipeline;
  ShadingMode shading = ShadingMode::flat;
  PainterKey painter_key = PainterKey::mean;
  BspOptions bsp;
  bool shadows = false;
  ShadowOptions shadow;
  TextureFilter texture_filter = TextureFilter::trilinear;
  PngCompression png_compression = PngCompression::fast;
  bool levels_given = false;        // false: the viewable levels are drawn
  std::vector<std::string> levels;  // ids of StaticGeometry::levels to draw
  CeilingMode ceilings = CeilingMode::automatic;
  // Coverage sub-samples per pixel (sample_pattern.hpp): 1 takes the polygon at the pixel centre;
  // 4, 8 or 16 resolve each pixel from the fragments visible in its sub-samples (docs/antialiasing.md).
  int antialias = 1;
  CullingMode culling = CullingMode::on;
  // Multiplies every light's intensity and the ambient's before shading (render() applies it once;
  // the background is a clear colour and is left alone). 1 changes no byte. auto_exposure: render()
  // picks the multiplier from a small pre-pass (docs/lighting.md "Exposure") and `exposure` is unused.
  double exposure = 1.0;
  bool auto_exposure = false;
};

struct RenderRequest {
  Scene scene;
  Camera camera;
  RenderOptions options;
};

}  // namespace rr
