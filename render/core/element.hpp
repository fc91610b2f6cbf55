// Which element of the scene description a runtime object came from: its kind and index (for an
// opening, its wall's index and its own). Runtime data (soup objects, placement warnings) holds
// these; the boundary turns them into JSON Pointers once (render/scene_io/element_pointer.hpp).
#pragma once

#include <cstddef>
#include <cstdint>

namespace rr {

enum class ElementKind : uint8_t { scene, floor, wall, opening, solid, room };

struct ElementRef {
  ElementKind kind = ElementKind::scene;
  uint32_t index = 0;    // the wall's or the solid's index; an opening's wall
  uint32_t opening = 0;  // an opening's index within its wall

  static ElementRef floor() { return {ElementKind::floor}; }
  static ElementRef wall(std::size_t w) { return {ElementKind::wall, uint32_t(w)}; }
  static ElementRef opening_of(std::size_t w, std::size_t k) {
    return {ElementKind::opening, uint32_t(w), uint32_t(k)};
  }
  static ElementRef solid(std::size_t s) { return {ElementKind::solid, uint32_t(s)}; }
  static ElementRef room(std::size_t r) { return {ElementKind::room, uint32_t(r)}; }
  friend bool operator==(const ElementRef&, const ElementRef&) = default;
};

}  // namespace rr
