// The splitter choice of the BSP build (bsp_build.cpp), apart so that tests can hold it to the plain
// definition. In: a node's polygons (indices into a soup), the options and the classification band;
// out: the splitter plane (a polygon's, or a free plane through the polygons' median when every
// polygon lies on one side of the best one) and, where known, every polygon's side of it.
#pragma once

#include "render/core/polygon_ops.hpp"
#include "render/core/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace rr::bsp_detail {

// A polygon's side as a bit set: 1 = a vertex in front, 2 = a vertex behind (3 = spanning, 0 = on).
enum : uint8_t { side_on = 0, side_front = 1, side_back = 2, side_spanning = 3 };

// Nodes with fewer polygons than this are never split by a free plane: a convex run that short costs
// less as a chain than the splits a free plane makes.
constexpr size_t kFreeSplitMin = 64;

// Sampled polygons classified between two checks of a candidate's lower bound.
constexpr size_t kScoreBlock = 64;

struct SplitCounts {
  size_t by_side[4] = {0, 0, 0, 0};  // indexed by side_*
  double score(const BspOptions& o) const {
    const double front = double(by_side[side_front]), back = double(by_side[side_back]);
    return o.w1 * std::abs(front - back) + o.w2 * double(by_side[side_spanning]) + o.w3 * double(by_side[side_on]);
  }
  // The least score() can become once `remaining` more polygons are counted: each term at its
  // least over the counts still possible. Rounding is monotonic, so score() >= lower_bound() holds
  // for the computed values too, and a candidate with lower_bound() >= the best score cannot win.
  double lower_bound(const BspOptions& o, size_t remaining) const {
    const double r = double(remaining);
    const double imbalance = std::abs(double(by_side[side_front]) - double(by_side[side_back]));
    const double splits = double(by_side[side_spanning]), on = double(by_side[side_on]);
    return (o.w1 >= 0.0 ? o.w1 * std::max(0.0, imbalance - r) : o.w1 * (imbalance + r)) +
           (o.w2 >= 0.0 ? o.w2 * splits : o.w2 * (splits + r)) + (o.w3 >= 0.0 ? o.w3 * on : o.w3 * (on + r));
  }
};

struct SplitChoice {
  Plane plane;
  int64_t polygon = -1;        // the splitter's index in the soup, -1 for a free plane
  std::vector<uint8_t> sides;  // every polygon's side (side_*), in the node's order; empty: not known
};

// Chooses a node's splitter; its buffers are reused from node to node.
class SplitterChooser {
 public:
  // The candidate polygon with the lowest score over the sampled polygons (bsp.hpp), ties to the
  // first; `counts` gets its sampled counts.
  uint32_t best_polygon(const PolygonSoup& soup, std::span<const uint32_t> polygons, const BspOptions& options,
                        double epsilon, CancelMeter& meter, SplitCounts& counts);
  // The node's splitter, valid until the next call.
  const SplitChoice& choose(const PolygonSoup& soup, std::span<const uint32_t> polygons, const BspOptions& options,
                            double epsilon, CancelMeter& meter);

 private:
  void gather(const PolygonSoup& soup, std::span<const uint32_t> polygons);
  // Classifies the sample against `plane` into `counts` and `sides`; false (counts partial) as soon
  // as its score cannot fall below `bound`.
  bool classify_sample(const Plane& plane, double epsilon, const BspOptions& options, double bound, SplitCounts& counts,
                       std::vector<uint8_t>& sides);
  bool try_free_plane(const PolygonSoup& soup, std::span<const uint32_t> polygons, const BspOptions& options,
                      double epsilon, double best_score, SplitChoice& out);

  // The sampled polygons' vertices as three coordinate arrays of `slots_` rows (a polygon's k-th
  // vertex at [k * sampled_ + its position in the sample]), so that each row streams.
  std::vector<double> x_, y_, z_;
  size_t sampled_ = 0, slots_ = 0;
  std::vector<uint8_t> current_, best_;
  SplitChoice choice_;
  std::vector<double> keys_;
  bool sample_is_all_ = false;
};

}  // namespace rr::bsp_detail
