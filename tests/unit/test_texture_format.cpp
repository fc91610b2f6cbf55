// Textures in the request format: every surface's texture member read into its struct (angles in
// radians, white where a textured surface has no colour), each distinct image decoded once per
// request, the caps (413 at the image's pointer, a 100,000 x 100,000 header refused from its header
// alone) and unreadable images (422 at the pointer); options.texture_filter; mesh uvs in the JSON
// mesh form and in the content id only when present.
#include "render/core/image.hpp"
#include "render/core/mesh_data.hpp"
#include "render/core/scene_names.hpp"
#include "render/core/texture.hpp"
#include "render/scene_io/mesh_json.hpp"
#include "render/scene_io/scene_json.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>
#include <set>

namespace rr {
namespace {

using nlohmann::json;

// A real PNG of w x h pixels of one colour, as a data: URI.
std::string png_uri(int w, int h, Color fill = Color{0.5f, 0.25f, 1.0f}) {
  return "data:image/png;base64," + testing::base64_encode(encode_png(Image(w, h, fill)));
}

json texture(const std::string& image) { return {{"image", image}}; }

json one_solid(json solid) { return {{"scene", {{"solids", {std::move(solid)}}}}}; }

// The pointer and kind of the first problem of a refused request.
std::pair<std::string, InputError::Kind> refusal(const json& request, const ParseLimits& limits = {}) {
  try {
    request_from_json(request, limits);
  } catch (const InputError& e) {
    return {e.pointer(), e.kind()};
  }
  return {"accepted", InputError::Kind::invalid};
}

TEST(SceneJsonTextures, EverySurfaceReadsItsTexture) {
  const std::string image = png_uri(2, 3);
  json tex = {{"image", image}, {"width", 0.5}, {"height", 2}, {"x_offset", 0.25}, {"y_offset", -1}, {"angle", 90}};
  json request = {{"scene",
                   {{"floor", {{"cells", {2, 2}}, {"texture", tex}}},
                    {"walls",
                     {{{"start", {0, 0}},
                       {"end", {4, 0}},
                       {"color", "#ff0000"},
                       {"left_texture", texture(image)},
                       {"right_color", "#00ff00"}}}},
                    {"rooms",
                     {{{"points", {{0, 0}, {1, 0}, {0, 1}}},
                       {"floor_texture", texture(image)},
                       {"ceiling_color", "#0000ff"},
                       {"ceiling_texture", texture(image)}}}},
                    {"solids",
                     {{{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"texture", texture(image)}},
                      {{"type", "piece"},
                       {"center", {0, 0}},
                       {"size", {1, 1, 1}},
                       {"color", "#808080"},
                       {"texture", texture(image)},
                       {"parts",
                        {{{"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {"faces", {{0, 1, 2}}}},
                         {{"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
                          {"faces", {{0, 1, 2}}},
                          {"uvs", {{0, 0}, {1, 0}, {0, 1}}},
                          {"texture", texture(image)}}}}}}}}}};
  const RenderRequest r = request_from_json(request);
  const StaticGeometry& g = r.scene.geometry;
  const Color white{1.0f};

  ASSERT_TRUE(g.floor.texture);
  const SurfaceTexture& t = *g.floor.texture;
  EXPECT_EQ(t.image, image);
  EXPECT_EQ(t.width, 0.5);
  EXPECT_EQ(t.height, 2.0);
  EXPECT_EQ(t.x_offset, 0.25);
  EXPECT_EQ(t.y_offset, -1.0);
  EXPECT_NEAR(t.angle, std::numbers::pi / 2, 1e-15);  // degrees in JSON, radians in the struct
  ASSERT_TRUE(t.decoded);
  EXPECT_EQ(g.floor.colors, (std::vector<Color>{white, white}));

  const Wall& wall = g.walls[0];
  ASSERT_TRUE(wall.left_texture);
  EXPECT_FALSE(wall.right_texture);
  EXPECT_EQ(wall.left_color, white);  // textured, no left_color: white, not the wall's color
  EXPECT_EQ(wall.right_color, (Color{0.0f, 1.0f, 0.0f}));
  EXPECT_EQ(wall.color, (Color{1.0f, 0.0f, 0.0f}));
  EXPECT_EQ(wall.left_texture->width, 1.0);  // the defaults
  EXPECT_EQ(wall.left_texture->angle, 0.0);

  const Room& room = g.rooms[0];
  ASSERT_TRUE(room.floor_texture && room.ceiling_texture);
  EXPECT_EQ(room.floor_color, white);
  EXPECT_EQ(room.ceiling_color, (Color{0.0f, 0.0f, 1.0f}));  // an explicit colour multiplies the image

  ASSERT_TRUE(g.solids[0].texture);
  EXPECT_EQ(g.solids[0].color, white);
  const Solid& piece = g.solids[1];
  EXPECT_NE(piece.color, white);                     // given: it multiplies the piece's texture
  EXPECT_EQ(piece.parts[0].texture, piece.texture);  // a part takes the piece's texture and colour
  EXPECT_EQ(piece.parts[0].color, piece.color);
  ASSERT_TRUE(piece.parts[1].texture);
  EXPECT_EQ(piece.parts[1].color, white);  // its own texture and no colour
  EXPECT_EQ(piece.parts[1].mesh->uvs.size(), 3u);
}

TEST(SceneJsonTextures, UntexturedSurfacesKeepTheirDefaults) {
  const RenderRequest r =
      request_from_json({{"scene",
                          {{"walls", {{{"start", {0, 0}}, {"end", {4, 0}}}}},
                           {"rooms", {{{"points", {{0, 0}, {1, 0}, {0, 1}}}}}},
                           {"solids", {{{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}}}}}}});
  const StaticGeometry& g = r.scene.geometry;
  EXPECT_FALSE(g.walls[0].left_color || g.walls[0].right_color || g.walls[0].left_texture);
  EXPECT_FALSE(g.rooms[0].floor_texture || g.rooms[0].ceiling_texture);
  EXPECT_FALSE(g.solids[0].texture);
  EXPECT_EQ(g.solids[0].color, Color{0.7f});
  EXPECT_EQ(r.options.texture_filter, TextureFilter::trilinear);
}

// decode_texture makes a new image on every call, so one shared pointer means one decode.
TEST(SceneJsonTextures, OneDataUriIsDecodedOncePerRequest) {
  const std::string a = png_uri(4, 4), b = png_uri(4, 4, Color{0.0f});
  json solids = json::array();
  for (const std::string& image : {a, b, a, a, b}) {
    solids.push_back({{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"texture", texture(image)}});
  }
  const RenderRequest r = request_from_json({{"scene", {{"solids", solids}}}});
  std::set<const TextureImage*> images;
  for (const Solid& s : r.scene.geometry.solids) images.insert(s.texture->decoded.get());
  EXPECT_EQ(images.size(), 2u);
  const auto& s = r.scene.geometry.solids;
  EXPECT_EQ(s[0].texture->decoded, s[2].texture->decoded);
  EXPECT_EQ(s[1].texture->decoded, s[4].texture->decoded);
  EXPECT_NE(s[0].texture->decoded->content_id, s[1].texture->decoded->content_id);
}

TEST(SceneJsonTextures, ProblemsNameTheirPointers) {
  auto box_with = [](json tex) {
    return one_solid({{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"texture", std::move(tex)}});
  };
  using K = InputError::Kind;
  const std::string at = "/scene/solids/0/texture";
  EXPECT_EQ(refusal(box_with({{"width", 1}})), std::pair(at, K::invalid));  // image is required
  EXPECT_EQ(refusal(box_with(texture("http://example.com/a.png"))), std::pair(at + "/image", K::invalid));
  EXPECT_EQ(refusal(box_with(texture("0123456789abcdef"))), std::pair(at + "/image", K::invalid));
  EXPECT_EQ(refusal(box_with({{"image", 7}})), std::pair(at + "/image", K::invalid));
  EXPECT_EQ(refusal(box_with(texture("data:image/png;base64,@@@@"))), std::pair(at + "/image", K::invalid));
  EXPECT_EQ(refusal(box_with(texture("data:text/plain;base64," + testing::base64_encode("hello world")))),
            std::pair(at + "/image", K::invalid));
  EXPECT_EQ(refusal(box_with({{"image", png_uri(1, 1)}, {"width", 0}})), std::pair(at + "/width", K::invalid));
  EXPECT_EQ(refusal(box_with({{"image", png_uri(1, 1)}, {"height", -1}})), std::pair(at + "/height", K::invalid));
  EXPECT_EQ(refusal(box_with({{"image", png_uri(1, 1)}, {"scale", 2}})), std::pair(at + "/scale", K::invalid));
  EXPECT_EQ(refusal(one_solid({{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"texture", "a.png"}})),
            std::pair(at, K::invalid));

  // An id with no resolver (or one that knows no such image) names the stored image it missed.
  try {
    request_from_json(box_with(texture("0123456789abcdef")));
    ADD_FAILURE() << "an unknown stored image was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no stored image \"0123456789abcdef\""), std::string::npos) << e.what();
  }
  EXPECT_EQ(
      refusal(
          {{"scene",
            {{"walls", {{{"start", {0, 0}}, {"end", {4, 0}}, {"right_texture", texture("x")}, {"left_color", 3}}}}}}}),
      std::pair(std::string("/scene/walls/0/left_color"), K::invalid));
  EXPECT_EQ(refusal({{"options", {{"texture_filter", "cubic"}}}}),
            std::pair(std::string("/options/texture_filter"), K::invalid));
}

// A stored image named by id comes from the limits' resolver, asked once per request however many
// surfaces name it, and is the very image the same bytes' data: URI decodes to.
TEST(SceneJsonTextures, AnIdResolvesThroughTheLimitsOncePerRequest) {
  const std::string uri = png_uri(4, 2);
  std::vector<uint8_t> bytes;
  ASSERT_TRUE(decode_data_uri(uri, texture_image_bytes_cap, bytes, nullptr));
  std::shared_ptr<const TextureImage> stored = decode_texture(bytes, TextureLimits{}, nullptr);
  ASSERT_TRUE(stored);
  int asked = 0;
  ParseLimits limits;
  limits.resolve_texture = [&](const std::string& id) -> std::shared_ptr<const TextureImage> {
    ++asked;
    return id == stored->content_id ? stored : nullptr;
  };
  const json request = {
      {"scene",
       {{"floor", {{"cells", {1, 1}}, {"texture", texture(stored->content_id)}}},
        {"solids",
         {{{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"texture", texture(uri)}},
          {{"type", "box"}, {"center", {2, 0}}, {"size", {1, 1, 1}}, {"texture", texture(stored->content_id)}}}}}}};
  const RenderRequest parsed = request_from_json(request, limits);
  EXPECT_EQ(asked, 1);
  EXPECT_EQ(parsed.scene.geometry.floor.texture->decoded, stored);
  EXPECT_EQ(parsed.scene.geometry.solids[1].texture->decoded, stored);
  EXPECT_EQ(parsed.scene.geometry.solids[0].texture->decoded->content_id, stored->content_id);
  EXPECT_EQ(parsed.scene.geometry.solids[0].texture->decoded->levels[0].rgb, stored->levels[0].rgb);

  // An unknown id is told at every surface naming it, asking the resolver once.
  const json unknown = {
      {"scene",
       {{"floor", {{"cells", {1, 1}}, {"texture", texture("00000000000000ff")}}},
        {"solids",
         {{{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"texture", texture("00000000000000ff")}}}}}}};
  asked = 0;
  try {
    request_from_json(unknown, limits);
    ADD_FAILURE() << "an unknown stored image was accepted";
  } catch (const InputError& e) {
    ASSERT_EQ(e.errors().size(), 2u) << e.what();
    EXPECT_EQ(e.errors()[0].pointer, "/scene/floor/texture/image");
    EXPECT_EQ(e.errors()[1].pointer, "/scene/solids/0/texture/image");
  }
  EXPECT_EQ(asked, 1);
  // A stored image's pixels count against the request's decoded budget as an inline one's do.
  ParseLimits tight = limits;
  tight.max_texture_decoded_bytes = 4 * 2 * 4 - 1;
  EXPECT_EQ(refusal({{"scene", {{"floor", {{"cells", {1, 1}}, {"texture", texture(stored->content_id)}}}}}}, tight),
            std::pair(std::string("/scene/floor/texture/image"), InputError::Kind::too_large));
}

// The same unreadable image named twice is told at both places (and decoded once).
TEST(SceneJsonTextures, AnUnreadableImageIsToldWhereverItIsNamed) {
  const std::string bad = "data:image/png;base64," + testing::base64_encode("not an image at all");
  json request = {{"scene",
                   {{"floor", {{"cells", {1, 1}}, {"texture", texture(bad)}}},
                    {"rooms", {{{"points", {{0, 0}, {1, 0}, {0, 1}}}, {"ceiling_texture", texture(bad)}}}}}}};
  try {
    request_from_json(request);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.kind(), InputError::Kind::invalid);
    ASSERT_EQ(e.errors().size(), 2u);
    EXPECT_EQ(e.errors()[0].pointer, "/scene/floor/texture/image");
    EXPECT_EQ(e.errors()[1].pointer, "/scene/rooms/0/ceiling_texture/image");
    EXPECT_EQ(e.errors()[0].detail, e.errors()[1].detail);
  }
}

TEST(SceneJsonTextures, HugeHeaderIsRefusedFromTheHeaderAt413) {
  const std::string uri = "data:image/png;base64," + testing::base64_encode(testing::png_head(100'000, 100'000));
  json request = {{"scene", {{"rooms", {{{"points", {{0, 0}, {1, 0}, {0, 1}}}, {"floor_texture", texture(uri)}}}}}}};
  const auto [pointer, kind] = refusal(request);
  EXPECT_EQ(pointer, "/scene/rooms/0/floor_texture/image");
  // The URI holds a header and nothing else, so decoding it would fail as unreadable (422): a 413
  // shows that the header alone decided, before any pixel was decoded.
  EXPECT_EQ(kind, InputError::Kind::too_large);
}

TEST(SceneJsonTextures, ByteCapsAre413AtTheImage) {
  ParseLimits limits;
  limits.max_texture_image_bytes = 64;
  const std::string big = "data:image/png;base64," + testing::base64_encode(std::string(65, 'x'));
  EXPECT_EQ(refusal({{"scene", {{"floor", {{"cells", {1, 1}}, {"texture", texture(big)}}}}}}, limits),
            std::pair(std::string("/scene/floor/texture/image"), InputError::Kind::too_large));
  EXPECT_EQ(ParseLimits{}.max_texture_image_bytes, size_t{4} << 20);

  // The decoded total: room for one 8 x 8 image (4 bytes a pixel with its mip chain), not two. It
  // counts the decoded sizes, which only a decoder that keeps the image's size can show.
  TextureError error;
  const std::string png = encode_png(Image(8, 8, Color{0.0f}));
  const auto probe = decode_texture(std::span(reinterpret_cast<const uint8_t*>(png.data()), png.size()), {}, &error);
  if (!probe || probe->width() != 8) GTEST_SKIP() << "decode_texture does not decode yet (the format's stub)";
  ParseLimits total;
  total.max_texture_decoded_bytes = 8 * 8 * 4 + 10;
  json solids = json::array();
  for (const std::string& image : {png_uri(8, 8), png_uri(8, 8), png_uri(8, 8, Color{0.0f})}) {
    solids.push_back({{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"texture", texture(image)}});
  }
  EXPECT_EQ(refusal({{"scene", {{"solids", solids}}}}, total),
            std::pair(std::string("/scene/solids/2/texture/image"), InputError::Kind::too_large));
  solids.erase(2);
  EXPECT_NO_THROW(request_from_json({{"scene", {{"solids", solids}}}}, total));  // one image, named twice
}

TEST(SceneJsonTextures, TextureFilterNamesTheTable) {
  for (const auto& row : texture_filter_names) {
    EXPECT_EQ(request_from_json({{"options", {{"texture_filter", row.name}}}}).options.texture_filter, row.value);
  }
}

// --- mesh uvs ------------------------------------------------------------------------------------

const std::vector<Vec3> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {5, 5, 5}};
const std::vector<glm::dvec2> square_uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {9, 9}};

TEST(MeshUvs, FollowTheCanonicalOrder) {
  auto mesh = make_mesh_data(square, {{2, 3, 0, 1}}, {}, square_uvs);
  ASSERT_EQ(mesh->vertices.size(), 4u);  // the unused vertex is dropped, its uv with it
  ASSERT_EQ(mesh->uvs.size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    const size_t original = (k + 2) % 4;
    EXPECT_EQ(mesh->vertices[k], square[original]);
    EXPECT_EQ(mesh->uvs[k], square_uvs[original]);
  }
}

TEST(MeshUvs, HashedOnlyWhenPresent) {
  auto plain = make_mesh_data(square, {{0, 1, 2, 3}}, {});
  EXPECT_EQ(make_mesh_data(square, {{0, 1, 2, 3}}, {}, {})->content_id, plain->content_id);
  auto with_uvs = make_mesh_data(square, {{0, 1, 2, 3}}, {}, square_uvs);
  EXPECT_NE(with_uvs->content_id, plain->content_id);
  std::vector<glm::dvec2> moved = square_uvs;
  moved[1].x = 0.5;
  EXPECT_NE(make_mesh_data(square, {{0, 1, 2, 3}}, {}, moved)->content_id, with_uvs->content_id);
  // The JSON form writes them back, and reading that gives the same mesh.
  const json document = mesh_to_json(*with_uvs);
  ASSERT_TRUE(document.contains("uvs"));
  EXPECT_EQ(mesh_from_json(document, {})->content_id, with_uvs->content_id);
  EXPECT_FALSE(mesh_to_json(*plain).contains("uvs"));
}

TEST(MeshUvs, ProblemsNameTheirPointers) {
  const json base = {{"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {"faces", {{0, 1, 2}}}};
  auto pointer_of = [](const json& document) {
    try {
      mesh_from_json(document, {});
    } catch (const InputError& e) {
      return e.pointer();
    }
    return std::string("accepted");
  };
  json count = base;
  count["uvs"] = {{0, 0}, {1, 0}};
  EXPECT_EQ(pointer_of(count), "/uvs");
  json shape = base;
  shape["uvs"] = {{0, 0}, {1, 0, 0}, {0, 1}};
  EXPECT_EQ(pointer_of(shape), "/uvs/1");
  json text = base;
  text["uvs"] = {{0, 0}, {1, 0}, {0, "v"}};
  EXPECT_EQ(pointer_of(text), "/uvs/2/1");
  // A solid placing a stored mesh takes its uvs from it.
  EXPECT_EQ(refusal(one_solid({{"type", "mesh"}, {"ref", "0123456789abcdef"}, {"uvs", {{0, 0}}}})).first,
            "/scene/solids/0/uvs");
}

}  // namespace
}  // namespace rr
