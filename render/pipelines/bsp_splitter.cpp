// The splitter choice of the BSP build (bsp_build.hpp). Candidates are scored on a sample of the
// node's polygons copied once per node into coordinate arrays, so each candidate's classification is
// one streaming pass over cache-resident doubles; it computes every distance exactly as
// Plane::distance does, so the counts, and the chosen polygon, are those of classify_polygon.
#include "render/pipelines/bsp.hpp"
#include "render/pipelines/bsp_build.hpp"

#include "render/core/kernels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rr::bsp_detail {

namespace {

// Evenly spaced picks of `want` out of `n` (all of them when n <= want): deterministic, and spread
// over the whole node rather than its first polygons, which tessellation groups by object.
template <class Fn>
void for_each_sample(size_t n, size_t want, Fn&& fn) {
  if (n <= want) {
    for (size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  for (size_t k = 0; k < want; ++k) fn(k * n / want);
}

Vec3 centroid(std::span<const Vec3> points) {
  Vec3 sum(0.0);
  for (const Vec3& p : points) sum += p;
  return sum / double(points.size());
}

}  // namespace

void SplitterChooser::gather(const PolygonSoup& soup, std::span<const uint32_t> polygons) {
  sampled_ = 0, slots_ = 0;
  for_each_sample(polygons.size(), kScoreSample, [&](size_t i) {
    ++sampled_;
    slots_ = std::max(slots_, size_t(soup.polygons[polygons[i]].vertex_count));
  });
  x_.resize(slots_ * sampled_), y_.resize(slots_ * sampled_), z_.resize(slots_ * sampled_);
  size_t at = 0;
  for_each_sample(polygons.size(), kScoreSample, [&](size_t i) {
    const std::span<const Vec3> points = soup.points(soup.polygons[polygons[i]]);
    for (size_t k = 0; k < slots_; ++k) {
      // A polygon with fewer vertices repeats its last: a repeated vertex leaves its side as it is.
      const Vec3& p = points[std::min(k, points.size() - 1)];
      x_[k * sampled_ + at] = p.x, y_[k * sampled_ + at] = p.y, z_[k * sampled_ + at] = p.z;
    }
    ++at;
  });
  sample_is_all_ = polygons.size() <= kScoreSample;
}

bool SplitterChooser::classify_sample(const Plane& plane, double epsilon, const BspOptions& options, double bound,
                                      SplitCounts& counts, std::vector<uint8_t>& sides) {
  const size_t polygons = sampled_;
  sides.resize(polygons);
  counts = SplitCounts{};
  const double coefficients[4] = {plane.normal.x, plane.normal.y, plane.normal.z, plane.offset};
  const Kernels& simd = kernels();
  uint8_t* __restrict side = sides.data();
  static_assert(kScoreBlock <= classify_block);
  for (size_t p0 = 0; p0 < polygons; p0 += kScoreBlock) {
    const size_t count = std::min(polygons - p0, kScoreBlock);
    // Plane::distance's expression, operation for operation: dot(normal, p) - offset.
    simd.classify_points(x_.data() + p0, y_.data() + p0, z_.data() + p0, polygons, slots_, count, coefficients, epsilon,
                         side + p0, counts.by_side);
    const size_t p1 = p0 + count;
    if (p1 < polygons && !(counts.lower_bound(options, polygons - p1) < bound)) return false;
  }
  return true;
}

uint32_t SplitterChooser::best_polygon(const PolygonSoup& soup, std::span<const uint32_t> polygons,
                                       const BspOptions& options, double epsilon, CancelMeter& meter,
                                       SplitCounts& counts) {
  gather(soup, polygons);
  double best_score = std::numeric_limits<double>::infinity();
  uint32_t best = polygons[0];
  for_each_sample(polygons.size(), size_t(options.max_candidates), [&](size_t c) {
    meter.add(std::min(polygons.size(), kScoreSample));
    SplitCounts candidate;
    // A candidate whose score cannot fall below the best's is left as soon as that is certain.
    if (!classify_sample(plane_of(soup.polygons[polygons[c]]), epsilon, options, best_score, candidate, current_))
      return;
    const double score = candidate.score(options);
    if (score < best_score) {  // ties: the first candidate
      best_score = score, best = polygons[c], counts = candidate;
      std::swap(current_, best_);
    }
  });
  return best;
}

const SplitChoice& SplitterChooser::choose(const PolygonSoup& soup, std::span<const uint32_t> polygons,
                                           const BspOptions& options, double epsilon, CancelMeter& meter) {
  SplitCounts counts;
  const uint32_t best = best_polygon(soup, polygons, options, epsilon, meter, counts);
  // Every sampled polygon on one side of the best candidate: a convex run, which polygon planes
  // can only peel one plane at a time. A free plane through the middle may score better.
  const bool one_sided = counts.by_side[side_front] == 0 || counts.by_side[side_back] == 0;
  if (one_sided && try_free_plane(soup, polygons, options, epsilon, counts.score(options), choice_)) {
    meter.add(polygons.size());
    return choice_;
  }
  choice_.plane = plane_of(soup.polygons[best]);
  choice_.polygon = best;
  choice_.sides.clear();
  if (sample_is_all_) choice_.sides.swap(best_);  // best_ is refilled by the next node's scoring
  return choice_;
}

// The plane across the widest axis of the polygons' centroids, through their median: it halves
// the node whatever its shape. Taken only when its sampled score beats the best polygon's, when
// both sides keep a whole polygon (so both children are smaller than the node), and when no polygon
// of a plane group (coplanar overlaps, whose ties the splitter's own node decides by id) reaches
// into the band, where overlapping parts could land in different subtrees.
bool SplitterChooser::try_free_plane(const PolygonSoup& soup, std::span<const uint32_t> polygons,
                                     const BspOptions& options, double epsilon, double best_score, SplitChoice& out) {
  if (polygons.size() < kFreeSplitMin) return false;
  Vec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  for (uint32_t index : polygons) {
    const Vec3 c = centroid(soup.points(soup.polygons[index]));
    lo = glm::min(lo, c), hi = glm::max(hi, c);
  }
  const Vec3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  if (!(extent[axis] > 2.0 * epsilon)) return false;
  keys_.clear();
  for (uint32_t index : polygons) keys_.push_back(centroid(soup.points(soup.polygons[index]))[axis]);
  std::nth_element(keys_.begin(), keys_.begin() + std::ptrdiff_t(keys_.size() / 2), keys_.end());
  Plane plane;
  plane.normal = Vec3(0.0);
  plane.normal[axis] = 1.0;
  plane.offset = keys_[keys_.size() / 2];
  SplitCounts counts;
  if (!classify_sample(plane, epsilon, options, best_score, counts, current_) ||
      !(counts.score(options) < best_score)) {
    return false;
  }

  out.sides.resize(polygons.size());
  size_t whole[4] = {0, 0, 0, 0};
  for (size_t k = 0; k < polygons.size(); ++k) {
    const Polygon& poly = soup.polygons[polygons[k]];
    uint8_t side = 0;
    bool in_band = false;
    for (const Vec3& p : soup.points(poly)) {
      const double d = plane.distance(p);
      side |= uint8_t(uint8_t(d > epsilon) | uint8_t(uint8_t(d < -epsilon) << 1));
      in_band |= std::abs(d) <= epsilon;
    }
    if (in_band && poly.plane_group != 0) return false;
    out.sides[k] = side;
    ++whole[side];
  }
  if (whole[side_front] == 0 || whole[side_back] == 0) return false;
  out.plane = plane;
  out.polygon = -1;
  return true;
}

}  // namespace rr::bsp_detail
