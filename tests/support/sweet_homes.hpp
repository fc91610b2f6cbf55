// The Sweet Home 3D homes of ../shared/data/floorplans/sweethome3d as a user sends them: each
// <Name>.xml zipped with the furniture/ models (and their .mtl) it names, and copies of a home moved
// apart (every plan coordinate shifted) so that each copy is a scene of its own.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rr::testing {

// The homes' XML files, sorted by name; empty when ../shared/data is absent.
std::vector<std::filesystem::path> sweet_home_files();

// Every `model` attribute of a home, in order of first appearance.
std::vector<std::string> sweet_home_model_names(const std::string& xml);

// The material libraries an OBJ names.
std::vector<std::string> obj_material_libraries(const std::string& obj);

// The data set's layout: <Name>.xml (with `xml` as its content, the file's own when empty) and
// furniture/<model file> (+ its .mtl) for each model it names.
std::string sweet_home_zip(const std::filesystem::path& home, const std::string& xml = "");

// `xml` with every plan coordinate (x, y, xStart, yStart, xEnd, yEnd of walls, rooms' points,
// furniture, cameras, labels) moved by (dx_cm, dy_cm); a light source's and a sash's coordinates
// are relative to their piece and stay.
std::string moved_sweet_home(const std::string& xml, double dx_cm, double dy_cm);

// Home `i` of a sequence of distinct homes: the nine in name order, then again each moved 50 m
// further east per round (i / 9 rounds), zipped as sweet_home_zip does. Its name says which.
struct DistinctHome {
  std::string name;  // "Studio+2": Studio moved twice
  std::string zip;
};
DistinctHome distinct_sweet_home(size_t i);

}  // namespace rr::testing
