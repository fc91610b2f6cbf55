// OBJ import with textures: vt per face corner splits vertices (position, vt, vn) only in textured
// groups, so an OBJ without textures imports as before; map_Kd (after its options, relative to its
// .mtl) becomes the solid's texture as a data: URI; missing images and map_d warn. And the fireplace
// room of ../shared with its four bitmaps (skipped without it).
#include "import_test_util.hpp"
#include "render/core/image.hpp"
#include "render/core/texture.hpp"
#include "render/import/import.hpp"
#include "render/import/import_files.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace {

using nlohmann::json;

// Two quads sharing an edge whose corners have different vt on each side (a seam), as a texture
// atlas puts them.
const char* seam_obj = R"(mtllib mtl/room.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 2 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 0.5
usemtl Wood
f 1/1 2/2 3/3 4/4
f 2/5 5/2 6/3 3/5
)";

std::string tex_png() { return rr::encode_png(rr::Image(2, 2, rr::Color{0.6f, 0.4f, 0.2f})); }

rr::ImportOptions with_files(std::map<std::string, std::string> files, std::vector<std::string>* asked = nullptr) {
  rr::ImportOptions options;
  options.read_companion = [files, asked](const std::string& name) -> std::optional<std::string> {
    if (asked) asked->push_back(name);
    auto it = files.find(name);
    if (it == files.end()) return std::nullopt;
    return it->second;
  };
  return options;
}

bool has_warning(const rr::ImportResult& r, const std::string& part) {
  for (const std::string& w : r.warnings) {
    if (w.find(part) != std::string::npos) return true;
  }
  return false;
}

TEST(ImportObjTextures, VtSplitsVerticesOfTexturedGroups) {
  std::vector<std::string> asked;
  const rr::ImportResult r = rr::import_obj(
      seam_obj, with_files({{"mtl/room.mtl", "newmtl Wood\nmap_Kd -s 2 2 1 -bm 0.5 -clamp on tex/oak planks.png\n"},
                            {"mtl/tex/oak planks.png", tex_png()}},
                           &asked));
  const json& mesh = r.request["scene"]["solids"][0];
  ASSERT_TRUE(mesh.contains("uvs"));
  EXPECT_EQ(mesh["vertices"].size(), 8u);  // 6 positions, the shared edge's two split by their vt
  EXPECT_EQ(mesh["uvs"].size(), 8u);
  EXPECT_EQ(mesh["uvs"][0], json({0.0, 0.0}));
  EXPECT_EQ(mesh["uvs"][4], json({0.5, 0.5}));
  // The path after the options, relative to the .mtl's folder; the image read once.
  EXPECT_EQ(std::count(asked.begin(), asked.end(), "mtl/tex/oak planks.png"), 1);
  const std::string image = mesh["texture"]["image"];
  EXPECT_TRUE(image.starts_with("data:image/png;base64,"));
  EXPECT_EQ(mesh["color"], json({1.0, 1.0, 1.0}));  // map_Kd without Kd: the image as it is
  EXPECT_TRUE(has_warning(r, "-o, -s and -t are not applied"));

  // The request reads: the solid is textured by its uvs.
  const rr::RenderRequest request = rr::request_from_json(r.request);
  const rr::Solid& solid = request.scene.geometry.solids[0];
  ASSERT_TRUE(solid.texture && solid.texture->decoded);
  EXPECT_EQ(solid.mesh->uvs.size(), 8u);
}

TEST(ImportObjTextures, WithoutATextureTheMeshIsAsBefore) {
  // The same OBJ with Kd only: vt is read but not used, so the vertices stay one per position.
  const rr::ImportResult plain = rr::import_obj(seam_obj, with_files({{"mtl/room.mtl", "newmtl Wood\nKd 1 0 0\n"}}));
  const json& mesh = plain.request["scene"]["solids"][0];
  EXPECT_FALSE(mesh.contains("uvs") || mesh.contains("texture"));
  EXPECT_EQ(mesh["vertices"].size(), 6u);

  // And the OBJ without any vt gives the very same mesh.
  std::string no_vt = seam_obj;
  for (const char* corner : {"/1 ", "/2 ", "/3 ", "/4\n", "/5 ", "/2 ", "/3 ", "/5\n"}) {
    no_vt.replace(no_vt.find(corner), std::string(corner).size() - 1, "");
  }
  const rr::ImportResult without = rr::import_obj(no_vt, with_files({{"mtl/room.mtl", "newmtl Wood\nKd 1 0 0\n"}}));
  EXPECT_EQ(without.request, plain.request);
}

TEST(ImportObjTextures, MissingImagesAndAlphaMapsWarn) {
  const rr::ImportResult r = rr::import_obj(
      seam_obj,
      with_files({{"mtl/room.mtl", "newmtl Wood\nKd 0.5 0.5 0.5\nmap_Kd gone.png\nmap_d -imfchan m a.png\n"}}));
  const json& mesh = r.request["scene"]["solids"][0];
  EXPECT_FALSE(mesh.contains("texture") || mesh.contains("uvs"));
  EXPECT_TRUE(has_warning(r, "texture 'mtl/gone.png' is not available")) << r.warnings.size();
  EXPECT_TRUE(has_warning(r, "alpha cut-outs (map_d) are not supported"));

  // A textured group whose faces lack vt is drawn untextured, and says so.
  std::string no_vt = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Wood\nf 1 2 3\n";
  const rr::ImportResult r2 =
      rr::import_obj(no_vt, with_files({{"m.mtl", "newmtl Wood\nmap_Kd t.png\n"}, {"t.png", tex_png()}}));
  EXPECT_FALSE(r2.request["scene"]["solids"][0].contains("texture"));
  EXPECT_TRUE(has_warning(r2, "without texture coordinates"));

  // Not a PNG or JPEG, or over the per-image cap: untextured with a warning.
  const rr::ImportResult r3 = rr::import_obj(
      seam_obj, with_files({{"mtl/room.mtl", "newmtl Wood\nmap_Kd t.bmp\n"}, {"mtl/t.bmp", "BM not really"}}));
  EXPECT_TRUE(has_warning(r3, "neither a PNG nor a JPEG"));
  const rr::ImportResult r4 =
      rr::import_obj(seam_obj, with_files({{"mtl/room.mtl", "newmtl Wood\nmap_Kd t.png\n"},
                                           {"mtl/t.png", std::string(rr::texture_image_bytes_cap + 1, 'x')}}));
  EXPECT_TRUE(has_warning(r4, "a request takes per image"));
}

TEST(ImportObjTextures, FireplaceRoomImportsWithItsTextures) {
  const auto data = rr::testing::shared_data_dir();
  const std::filesystem::path obj = data ? *data / "meshes" / "fireplace_room" / "fireplace_room_uv.obj" : "";
  if (!data || !std::filesystem::exists(obj)) GTEST_SKIP() << "no fireplace room (../shared/data absent)";
  const rr::ImportResult r = rr::import_path(obj, std::nullopt, {});
  std::set<std::string> textured, images;
  size_t faces = 0;
  for (const json& solid : r.request["scene"]["solids"]) {
    faces += solid["faces"].size();
    if (!solid.contains("texture")) continue;
    EXPECT_TRUE(solid.contains("uvs")) << solid["id"];
    const std::string id = solid["id"];  // "<group> / <material>"
    textured.insert(id.substr(id.rfind(" / ") + 3));
    images.insert(solid["texture"]["image"].get<std::string>());
  }
  EXPECT_EQ(textured, (std::set<std::string>{"Floor", "Leaves", "Painting", "TableWood"}));
  EXPECT_EQ(images.size(), 4u);
  for (const std::string& image : images) {
    EXPECT_TRUE(image.starts_with("data:image/jpeg;base64,") || image.starts_with("data:image/png;base64,"));
  }
  EXPECT_GE(faces, 15'269u);  // non-planar faces may be split, none are lost
  EXPECT_TRUE(has_warning(r, "alpha cut-outs (map_d) are not supported, these materials are drawn opaque: Leaves"));

  // Read as a request: each bitmap decoded once, shared by every solid that names it.
  const rr::RenderRequest request = rr::request_from_json(r.request);
  std::set<const rr::TextureImage*> decoded;
  for (const rr::Solid& s : request.scene.geometry.solids) {
    if (s.texture) decoded.insert(s.texture->decoded.get());
  }
  EXPECT_EQ(decoded.size(), 4u);
}

}  // namespace
