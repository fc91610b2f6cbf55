// Shading: analytic values of the lighting model in every mode, Phong against the per-point
// reference, what Gouraud and Phong show that flat cannot, the count of light evaluations, and that
// fragments of a polygon (as the painter and BSP pipelines draw them) shade like the whole polygon.
// Pixel tolerances are in 8-bit levels: to_byte rounds, so an exact value is within 0.5 level; 1
// level more absorbs the float per-pixel path.
#include "render/core/polygon_ops.hpp"
#include "render/core/scene_id.hpp"
#include "render/core/shading.hpp"
#include "render/core/shadow.hpp"
#include "support/render_helpers.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace rr {
namespace {

using nlohmann::json;
using testing::render_json;
using testing::SceneRender;

const char* const kModes[] = {"flat", "gouraud", "phong"};

// One square floor cell of `size` metres centred on the origin, grey #808080, ambient 0.2.
json floor_request(double size, const std::string& shading, json lights) {
  return {{"scene",
           {{"ambient", {{"intensity", 0.2}}},
            {"floor",
             {{"origin", {-size / 2, -size / 2}},
              {"cells", {1, 1}},
              {"cell_size", size},
              {"colors", {"#808080", "#808080"}}}},
            {"lights", std::move(lights)}}},
          {"camera", {{"position", {0, 6, 5}}, {"target", {0, 0, 0}}}},
          {"options", {{"width", 160}, {"height", 120}, {"shading", shading}}}};
}

TEST(Shading, DirectionalLightOnSquareFloorHasTheLambertValueInEveryMode) {
  // Value = colour * (ambient + intensity * cos(angle from vertical)); every floor pixel has it,
  // so their mean is within the 0.5 level of to_byte's rounding of the exact value.
  for (double angle_deg : {0.0, 40.0, 75.0}) {
    const double a = radians(angle_deg);
    const double expected = 128.0 * (0.2 + 0.9 * std::cos(a));  // #808080 = 128/255
    for (const char* mode : kModes) {
      SCOPED_TRACE(std::string(mode) + " at " + std::to_string(angle_deg) + " degrees");
      json lights =
          json::array({{{"type", "directional"}, {"direction", {std::sin(a), -std::cos(a), 0.0}}, {"intensity", 0.9}}});
      auto r = render_json(floor_request(8.0, mode, lights));
      const Image& img = r.result.frame.image;
      double sum = 0.0, worst = 0.0;
      size_t count = 0;
      for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
          if (r.result.frame.ids.at(x, y) == background_id) continue;
          const double v = testing::channel(img, x, y);
          sum += v;
          worst = std::max(worst, std::abs(v - expected));
          ++count;
        }
      }
      ASSERT_GT(count, 5000u);
      EXPECT_NEAR(sum / double(count), expected, 0.5);
      EXPECT_LE(worst, 1.0);
    }
  }
}

TEST(Shading, PhongMatchesTheReferenceModelAtEveryPixel) {
  // A point light with attenuation and a coloured specular lobe: the per-pixel float path against
  // shade_point in doubles at the ray-cast floor point of each pixel centre.
  json lights = json::array({{{"type", "point"},
                              {"position", {0.5, 1.5, -0.5}},
                              {"intensity", 1.2},
                              {"attenuation", {1.0, 0.1, 0.05}},
                              {"color", "#fff0e0"}}});
  json request = floor_request(10.0, "phong", lights);
  request["scene"]["floor"]["material"] = {{"specular", 0.8}, {"shininess", 40}, {"specular_color", "#ffccaa"}};
  auto r = render_json(request);
  const Material& material = r.soup.materials[r.soup.polygons[0].material];
  size_t count = 0, off_by_one = 0;
  for (int y = 0; y < r.view.height; ++y) {
    for (int x = 0; x < r.view.width; ++x) {
      if (r.result.frame.ids.at(x, y) == background_id) continue;
      auto p = testing::pixel_on_plane(r.view, x, y, {0, 1, 0}, 0.0);
      ASSERT_TRUE(p);
      const Color ref = shade_point(r.request.scene, material, *p, {0, 1, 0}, r.view.eye);
      for (int c = 0; c < 3; ++c) {
        const int d = std::abs(int(testing::channel(r.result.frame.image, x, y, c)) - int(to_byte(ref[c])));
        ASSERT_LE(d, 1) << "pixel " << x << "," << y << " channel " << c;
        off_by_one += d;
      }
      ++count;
    }
  }
  EXPECT_GT(count, 5000u);
  EXPECT_LT(double(off_by_one), 0.01 * double(count * 3));  // rounding ties only
}

TEST(Shading, PhongShowsAHighlightOnALargeFloorThatGouraudMisses) {
  // A black floor 20 m wide with a sharp white specular lobe, a point light 1 m above its centre,
  // the eye at (0, 3, 6): the mirror point, where n.h = 1, is (0, 0, 1.5). Gouraud lights only the
  // four corners, 10 m away, where (n.h)^200 vanishes.
  json lights = json::array({{{"type", "point"}, {"position", {0, 1, 0}}}});
  json request = floor_request(20.0, "phong", lights);
  request["scene"]["floor"]["colors"] = {"#000000", "#000000"};
  request["scene"]["floor"]["material"] = {{"specular", 1.0}, {"shininess", 200}};
  request["camera"] = {{"position", {0, 3, 6}}, {"target", {0, 0, 0}}};
  request["options"]["width"] = 320;
  request["options"]["height"] = 240;
  auto brightest = [](const Image& img) {
    int best = -1, bx = 0, by = 0;
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x) {
        if (testing::channel(img, x, y) > best) best = testing::channel(img, x, y), bx = x, by = y;
      }
    }
    return std::array<int, 3>{best, bx, by};
  };
  auto phong = render_json(request);
  const auto [peak, px, py] = brightest(phong.result.frame.image);
  const Vec2 mirror = project_to_screen(phong.view, {0, 0, 1.5});
  EXPECT_GE(peak, 250);
  EXPECT_LE(std::abs(px + 0.5 - mirror.x), 2.0);
  EXPECT_LE(std::abs(py + 0.5 - mirror.y), 2.0);
  request["options"]["shading"] = "gouraud";
  EXPECT_LE(brightest(render_json(request).result.frame.image)[0], 2);
}

// Pixel values of each polygon id of an image.
std::map<uint32_t, std::set<int>> values_per_polygon(const SceneRender& r) {
  std::map<uint32_t, std::set<int>> out;
  for (int y = 0; y < r.view.height; ++y) {
    for (int x = 0; x < r.view.width; ++x) {
      const uint32_t id = r.result.frame.ids.at(x, y);
      if (id != background_id) out[id].insert(testing::channel(r.result.frame.image, x, y, 1));
    }
  }
  return out;
}

json cylinder_request(const std::string& shading, bool smooth) {
  return {{"scene",
           {{"solids",
             {{{"type", "cylinder"},
               {"center", {0, 0}},
               {"radius", 1},
               {"height", 2},
               {"segments", 12},
               {"smooth", smooth},
               {"material", {{"specular", 0.5}, {"shininess", 20}}}}}},
            {"lights", {{{"type", "directional"}, {"direction", {-1, -0.3, -0.4}}}}}}},
          {"camera", {{"position", {0, 1.5, 5}}, {"target", {0, 1, 0}}}},
          {"options", {{"width", 200}, {"height", 150}, {"shading", shading}}}};
}

TEST(Shading, GouraudAndPhongDifferFromFlatOnASmoothCylinder) {
  // Flat gives each side quad one value. With shared averaged normals the lit side quads vary
  // across their width under Gouraud and Phong.
  for (const char* mode : kModes) {
    SCOPED_TRACE(mode);
    auto r = render_json(cylinder_request(mode, true));
    int varying = 0;
    for (const auto& [id, values] : values_per_polygon(r)) {
      if (id < 12 && *values.rbegin() - *values.begin() >= 8) ++varying;
      if (std::string(mode) == "flat") {
        EXPECT_EQ(values.size(), 1u) << "polygon " << id;
      }
    }
    if (std::string(mode) != "flat") {
      EXPECT_GE(varying, 3);
    }
  }
}

TEST(Shading, FacetedCylinderLooksFlatInEveryMode) {
  // Faceted solids keep face normals: with a directional light (no position dependence) and the
  // specular off, Gouraud and Phong must reproduce flat shading to the rounding level.
  auto request = [](const char* mode) {
    json j = cylinder_request(mode, false);
    j["scene"]["solids"][0].erase("material");
    return render_json(j);
  };
  const Image flat = request("flat").result.frame.image;
  for (const char* mode : {"gouraud", "phong"}) {
    const Image other = request(mode).result.frame.image;
    int worst = 0;
    for (size_t i = 0; i < flat.rgb.size(); ++i)
      worst = std::max(worst, std::abs(int(flat.rgb[i]) - int(other.rgb[i])));
    EXPECT_LE(worst, 1) << mode;
  }
}

TEST(Shading, CountsLightEvaluationsAndSkipsLightsBehindThePlane) {
  // One open floor polygon seen from above; of four lights, the two below its plane never count.
  json lights = json::array({{{"type", "directional"}, {"direction", {0.3, -1, 0}}},
                             {{"type", "directional"}, {"direction", {0, 1, 0}}},
                             {{"type", "point"}, {"position", {0, -1, 0}}},
                             {{"type", "point"}, {"position", {1, 2, 0}}}});
  for (const char* mode : kModes) {
    SCOPED_TRACE(mode);
    auto r = render_json(floor_request(4.0, mode, lights));
    const std::string m = mode;
    size_t pixels = 0;
    for (uint32_t id : r.result.frame.ids.ids) pixels += id != background_id;
    const size_t expected = m == "flat" ? 2 : m == "gouraud" ? 2 * 4 : 2 * pixels;
    EXPECT_EQ(r.result.stats.lights_evaluated, expected);
  }
  // A closed box: the camera sees +X, +Y and +Z; a light travelling along (-1, -1, 0) reaches +X
  // and +Y only (it grazes +Z), and the hidden faces are never prepared.
  json box = {{"scene",
               {{"solids", {{{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}}}},
                {"lights", {{{"type", "directional"}, {"direction", {-1, -1, 0}}}}}}},
              {"camera", {{"position", {3, 2, 4}}, {"target", {0, 0.5, 0}}}},
              {"options", {{"width", 64}, {"height", 48}}}};
  EXPECT_EQ(render_json(box).result.stats.lights_evaluated, 2u);
  box["options"]["shading"] = "gouraud";
  EXPECT_EQ(render_json(box).result.stats.lights_evaluated, 8u);
}

// Draws `soup` (all of it, in index order, no depth test) the way a priority pipeline does.
Frame draw_soup(const FrameInput& input, const PolygonSoup& soup) {
  Frame frame{Image(input.view.width, input.view.height, Color(0.0f)), IdBuffer(input.view.width, input.view.height)};
  FrameTarget target{frame.image, frame.ids, nullptr, {0, 0, input.view.width, input.view.height}};
  DrawScratch scratch;
  SurfaceShader shader(input, soup);
  for (uint32_t i = 0; i < soup.polygons.size(); ++i) shader.prepare(i);
  for (uint32_t i = 0; i < soup.polygons.size(); ++i) {
    if (!project_polygon(input.view, soup, soup.polygons[i], scratch)) continue;
    shader.bind(i, scratch);
    draw_projected(target, scratch, soup.polygons[i].id, 1.0f, DepthMode::none,
                   [&](const Fragment& f, size_t k) { return shader.fragment(f, k); });
  }
  return frame;
}

TEST(Shading, FragmentsOfAPolygonShadeLikeTheWholePolygon) {
  // The painter and BSP pipelines draw fragments from their own soup; shading (Gouraud colours,
  // Phong positions, shadow lookups) must follow the source polygon. A big open triangle under a
  // point light with a box shadowing it is split by two planes into three fragments and compared
  // with the scene drawn from input.soup where the triangle shows. Pixels on the
  // cuts may round differently and shadow-edge pixels may flip, hence 0.2 % slack beyond 1 level.
  json request = {{"scene",
                   {{"solids",
                     {{{"type", "mesh"},
                       {"vertices", {{-4, 0, -3}, {4, 0, -3}, {0, 0, 4}}},
                       {"faces", {{0, 2, 1}}},
                       {"material", {{"specular", 0.6}}}},
                      {{"type", "box"}, {"center", {0.3, 0}}, {"size", {0.6, 1, 0.6}}}}},
                    {"lights", {{{"type", "point"}, {"position", {-1, 2.5, -1}}}}}}},
                  {"camera", {{"position", {0, 5, 5}}, {"target", {0, 0, 0}}}},
                  {"options", {{"width", 200}, {"height", 150}, {"shadows", true}}}};
  for (const char* mode : kModes) {
    SCOPED_TRACE(mode);
    request["options"]["shading"] = mode;
    RenderRequest req = request_from_json(request);
    PolygonSoup soup = tessellate(req.scene.geometry);
    ViewTransform view = make_view(req.camera, req.options.width, req.options.height);
    ShadowMaps maps = build_shadow_maps(req.scene, soup, view, req.options);
    ASSERT_FALSE(maps.empty());
    RenderContext context;
    FrameInput input{req.scene, soup, view, req.options, context, &maps};
    PolygonSoup pieces = make_fragment_soup(soup);
    SplitResult first = split_polygon(soup, soup.polygons[0], Plane{{1, 0, 0}, 0.7}, 1e-9, pieces);
    ASSERT_GE(first.front, 0);
    ASSERT_GE(first.back, 0);
    const Polygon back = pieces.polygons[size_t(first.back)];
    SplitResult second = split_polygon(pieces, back, Plane{glm::normalize(Vec3(1, 0, 2)), 0.3}, 1e-9, pieces);
    ASSERT_GE(second.front, 0);
    ASSERT_GE(second.back, 0);
    PolygonSoup fragments = make_fragment_soup(soup);
    for (int64_t k : {first.front, second.front, second.back})
      append_polygon(fragments, pieces, pieces.polygons[size_t(k)]);
    // The whole scene drawn from input.soup (the box over the triangle), against the fragments.
    const Frame whole = draw_soup(input, soup), split = draw_soup(input, fragments);
    size_t drawn = 0, differing = 0;
    for (size_t i = 0; i < whole.ids.ids.size(); ++i) {
      if (whole.ids.ids[i] != 0 || split.ids.ids[i] != 0) continue;
      ++drawn;
      for (size_t c = 0; c < 3; ++c)
        differing += std::abs(int(whole.image.rgb[3 * i + c]) - int(split.image.rgb[3 * i + c])) > 1;
    }
    EXPECT_GT(drawn, 5000u);
    EXPECT_LE(double(differing), 0.002 * double(drawn));
  }
}

TEST(Shading, MaterialsThatDifferOnlyInSpecularColourStayApart) {
  // Equal materials share an index and the scene id keys cached trees that carry material
  // indices, so the specular colour must take part in both.
  auto scene = [](const char* specular_color) {
    return json{{"scene",
                 {{"solids",
                   {{{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}, {"material", {{"specular", 0.5}}}},
                    {{"type", "box"},
                     {"center", {2, 0}},
                     {"size", {1, 1, 1}},
                     {"material", {{"specular", 0.5}, {"specular_color", specular_color}}}}}}}}};
  };
  RenderRequest white = request_from_json(scene("#ffffff")), red = request_from_json(scene("#ff0000"));
  EXPECT_NE(scene_id(white.scene.geometry), scene_id(red.scene.geometry));
  const PolygonSoup soup = tessellate(red.scene.geometry);
  ASSERT_EQ(soup.materials.size(), 2u);
  EXPECT_EQ(soup.materials[1].params.specular_color, Color(1.0f, 0.0f, 0.0f));
}

}  // namespace
}  // namespace rr
