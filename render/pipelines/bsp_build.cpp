// The BSP build (bsp.hpp, docs/bsp.md "Build"). In: a polygon soup and the BSP options; out: the
// tree, its fragments compacted in node order with T-junctions closed, and each node's bounds. Nodes
// above a size fixed by the input are split on one thread; the subtrees below it are built on
// rr::parallel_for, each into its own arrays, and spliced in a fixed order, so the tree does not
// depend on the thread count.
#include "render/pipelines/bsp_build.hpp"
#include "render/pipelines/bsp.hpp"

#include "render/core/parallel.hpp"
#include "render/core/timer.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>

namespace rr {

namespace {

using namespace bsp_detail;

// The build checks its token once per this many polygon classifications (a triangle's takes tens of
// nanoseconds, a split a few times that): well under a millisecond between checks even at the root
// of a 10^5-polygon soup, where one node's splitter choice alone is 10^4+ classifications.
constexpr size_t kClassificationsPerCheck = 16384;

// Subtrees of at most max(polygons / kSubtreesPerThreadedBuild, kMinParallelSubtree) polygons are
// built as tasks of their own: enough of them to balance two or more threads, none so small that
// copying its polygons out costs more than it saves.
constexpr size_t kSubtreesPerThreadedBuild = 16;
constexpr size_t kMinParallelSubtree = 4096;

// A node waiting to be split: its polygons are arena[begin, begin + count) of its builder.
struct Pending {
  int32_t node;
  size_t begin, count, depth;
};

// A subtree left to a task of its own: the node it fills in and its polygons (in the top part's soup).
struct Deferred {
  int32_t node;
  size_t depth;
  std::vector<uint32_t> polygons;
};

// One part of the tree: its own fragments, nodes (children after parents) and node polygon lists.
struct Part {
  PolygonSoup frags;
  std::vector<BspNode> nodes;
  std::vector<uint32_t> node_polygons;  // indices into frags
  size_t depth = 0, splits = 0;
};

// Splits nodes with an explicit stack: a long convex chain would overflow the call stack. The
// polygon lists of pending nodes live in one arena used as a stack (a node's children are pushed
// where its own list was), so no node allocates.
class Builder {
 public:
  Builder(Part& part, const BspOptions& options, double epsilon, const CancelToken* cancel, size_t defer_above)
      : part_(part),
        options_(options),
        epsilon_(epsilon),
        meter_(cancel, kClassificationsPerCheck),
        defer_above_(defer_above) {}

  // Builds the subtree of `polygons` (indices into the part's soup) into node `root`, leaving every
  // pending node of at most defer_above polygons in deferred().
  void run(int32_t root, const std::vector<uint32_t>& polygons, size_t depth) {
    arena_.assign(polygons.begin(), polygons.end());
    stack_.push_back({root, 0, polygons.size(), depth});
    while (!stack_.empty()) {
      const Pending work = stack_.back();
      stack_.pop_back();
      if (work.count <= defer_above_) {
        deferred_.push_back({work.node, work.depth, {arena_.begin() + std::ptrdiff_t(work.begin), arena_.end()}});
        arena_.resize(work.begin);
        continue;
      }
      split(work);
    }
  }
  std::vector<Deferred>& deferred() { return deferred_; }

 private:
  void split(const Pending& work);
  void push_child(int32_t parent, bool front_side, const std::vector<uint32_t>& polygons, size_t depth);

  Part& part_;
  const BspOptions& options_;
  double epsilon_;
  CancelMeter meter_;
  size_t defer_above_;
  SplitterChooser chooser_;
  std::vector<uint32_t> arena_, front_, back_;
  std::vector<Pending> stack_;
  std::vector<Deferred> deferred_;
};

void Builder::split(const Pending& work) {
  PolygonSoup& frags = part_.frags;
  part_.depth = std::max(part_.depth, work.depth);
  const std::span<const uint32_t> polygons(arena_.data() + work.begin, work.count);
  const SplitChoice& choice = chooser_.choose(frags, polygons, options_, epsilon_, meter_);
  // The splitter's plane group stays in its node whatever the band, so that ties there are decided
  // by id (below), as the reference decides them.
  const uint32_t group = choice.polygon >= 0 ? frags.polygons[size_t(choice.polygon)].plane_group : 0;
  front_.clear(), back_.clear();
  const uint32_t first = uint32_t(part_.node_polygons.size());
  for (size_t k = 0; k < polygons.size(); ++k) {
    const uint32_t index = polygons[k];
    meter_.add(1);
    const bool same_plane = group != 0 && frags.polygons[index].plane_group == group;
    PlaneSide side = PlaneSide::on;
    if (same_plane) {
      side = PlaneSide::on;
    } else if (!choice.sides.empty()) {
      constexpr PlaneSide by_bits[4] = {PlaneSide::on, PlaneSide::front, PlaneSide::back, PlaneSide::spanning};
      side = by_bits[choice.sides[k]];
    } else {
      side = classify_polygon(frags.points(frags.polygons[index]), choice.plane, epsilon_);
    }
    switch (side) {
      case PlaneSide::on:
        part_.node_polygons.push_back(index);
        break;
      case PlaneSide::front:
        front_.push_back(index);
        break;
      case PlaneSide::back:
        back_.push_back(index);
        break;
      case PlaneSide::spanning: {
        meter_.add(4);  // a split writes two new polygons
        SplitResult parts = split_polygon(frags, frags.polygons[index], choice.plane, epsilon_, frags);
        ++part_.splits;
        if (parts.front >= 0) front_.push_back(uint32_t(parts.front));
        if (parts.back >= 0) back_.push_back(uint32_t(parts.back));
        break;
      }
    }
  }
  BspNode& node = part_.nodes[size_t(work.node)];
  node.plane = choice.plane;
  node.first = first;
  node.count = uint32_t(part_.node_polygons.size()) - first;
  // A polygon splitter's own polygon is on its plane by construction, so its node keeps at least
  // one polygon and the recursion shrinks; only when the splitter's vertices are not within epsilon
  // of its own stored plane (a degenerate or non-planar input polygon) is it elsewhere: keep one here
  // rather than loop. A free plane keeps a whole polygon on each side (bsp_splitter.cpp), so its
  // node may hold none.
  if (node.count == 0 && choice.polygon >= 0) {
    part_.node_polygons.push_back(front_.empty() ? back_.back() : front_.back());
    (front_.empty() ? back_ : front_).pop_back();
    node.count = 1;
  }
  // Drawn back to front, the last of a node's polygons wins an overlap: highest id first, so the
  // lowest id wins ties as in the reference (docs/accuracy.md, "Ties"); front to back the reverse.
  if (node.count > 1) {  // most nodes hold one polygon: no sort, no sort buffer
    std::stable_sort(part_.node_polygons.begin() + first, part_.node_polygons.end(),
                     [&](uint32_t a, uint32_t b) { return frags.polygons[a].id > frags.polygons[b].id; });
  }
  arena_.resize(work.begin);  // the node's list is consumed: its children take its place
  push_child(work.node, false, back_, work.depth + 1);
  push_child(work.node, true, front_, work.depth + 1);
}

void Builder::push_child(int32_t parent, bool front_side, const std::vector<uint32_t>& polygons, size_t depth) {
  if (polygons.empty()) return;
  const int32_t child = int32_t(part_.nodes.size());
  part_.nodes.emplace_back();
  (front_side ? part_.nodes[size_t(parent)].front : part_.nodes[size_t(parent)].back) = child;
  stack_.push_back({child, arena_.size(), polygons.size(), depth});
  arena_.insert(arena_.end(), polygons.begin(), polygons.end());
}

void grow(Vec3& lo, Vec3& hi, Vec3 p) {
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

double scene_epsilon(const PolygonSoup& soup, double fraction) {
  if (soup.positions.empty()) return 0.0;
  Vec3 lo = soup.positions[0], hi = lo;
  double magnitude = 0.0;
  for (const Vec3& p : soup.positions) {
    grow(lo, hi, p);
    magnitude = std::max({magnitude, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  // A fraction of the scene's size, but never below what doubles can resolve at its coordinates: a
  // room 1e6 m from the origin still classifies its own vertices as on their own planes.
  return std::max(fraction * glm::length(hi - lo), 64.0 * DBL_EPSILON * magnitude);
}

// Runs fn(task) for every task on `threads` threads, rethrowing the first failure in task order
// (parallel_for's tasks must not throw).
template <class Fn>
void run_tasks(unsigned threads, size_t count, Fn&& fn) {
  std::vector<std::exception_ptr> errors(count);
  parallel_for(threads, count, [&](size_t task, unsigned) {
    try {
      fn(task);
    } catch (...) {
      errors[task] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

// Builds every deferred subtree into a part of its own, on `threads` threads, largest first.
std::vector<Part> build_deferred(const Part& top, const std::vector<Deferred>& deferred, const BspOptions& options,
                                 double epsilon, const CancelToken* cancel, unsigned threads) {
  std::vector<Part> parts(deferred.size());
  std::vector<size_t> order(deferred.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return deferred[a].polygons.size() > deferred[b].polygons.size(); });
  run_tasks(threads, deferred.size(), [&](size_t task) {
    check_cancel(cancel);  // a cancelled build starts no more subtrees
    const size_t d = order[task];
    Part& part = parts[d];
    part.frags = make_fragment_soup(top.frags);
    std::vector<uint32_t> local;
    local.reserve(deferred[d].polygons.size());
    for (uint32_t index : deferred[d].polygons)
      local.push_back(append_polygon(part.frags, top.frags, top.frags.polygons[index]));
    part.nodes.emplace_back();
    Builder builder(part, options, epsilon, cancel, 0);
    builder.run(0, local, deferred[d].depth);
  });
  return parts;
}

}  // namespace

namespace {

// A polygon of the output soup and where it is copied from.
struct Source {
  const PolygonSoup* soup;
  uint32_t polygon;
};

// A soup of the sources' polygons in order, copied in parallel ranges: each range writes only its
// own polygons and vertices, whose places are fixed beforehand.
PolygonSoup assemble(const PolygonSoup& like, const std::vector<Source>& sources, unsigned threads) {
  PolygonSoup out = make_fragment_soup(like);
  std::vector<uint32_t> first(sources.size() + 1, 0);
  for (size_t i = 0; i < sources.size(); ++i) {
    first[i + 1] = first[i] + sources[i].soup->polygons[sources[i].polygon].vertex_count;
  }
  out.polygons.resize(sources.size());
  out.positions.resize(first.back());
  out.normals.resize(first.back());
  constexpr size_t kRange = 16384;
  run_tasks(threads, (sources.size() + kRange - 1) / kRange, [&](size_t task) {
    for (size_t i = task * kRange; i < std::min(sources.size(), (task + 1) * kRange); ++i) {
      const PolygonSoup& from = *sources[i].soup;
      Polygon p = from.polygons[sources[i].polygon];
      std::copy_n(from.positions.begin() + p.first_vertex, p.vertex_count, out.positions.begin() + first[i]);
      std::copy_n(from.normals.begin() + p.first_vertex, p.vertex_count, out.normals.begin() + first[i]);
      p.first_vertex = first[i];
      out.polygons[i] = p;
    }
  });
  return out;
}

// The parts as one tree: the top part's nodes keep their indices, each deferred subtree's root
// fills its waiting node and its other nodes follow in deferral order (children still after their
// parents). Only the polygons the nodes hold are kept, in node order, so the tree's memory and its
// fragment count are what is drawn (a split polygon's original is replaced by its parts).
void splice(BspTree& tree, const Part& top, const std::vector<Deferred>& deferred, const std::vector<Part>& parts,
            const PolygonSoup& soup, unsigned threads) {
  struct Owner {
    const Part* part;
    size_t node;  // in the part
  };
  std::vector<Owner> owners;
  tree.nodes = top.nodes;
  for (size_t i = 0; i < top.nodes.size(); ++i) owners.push_back({&top, i});
  tree.depth = top.depth;
  tree.splits = top.splits;
  for (size_t d = 0; d < deferred.size(); ++d) {
    const Part& part = parts[d];
    const int32_t base = int32_t(tree.nodes.size()) - 1;
    auto global = [&](int32_t i) { return i < 0 ? -1 : i == 0 ? deferred[d].node : base + i; };
    for (size_t i = 0; i < part.nodes.size(); ++i) {
      BspNode node = part.nodes[i];
      node.front = global(node.front), node.back = global(node.back);
      if (i == 0) {
        tree.nodes[size_t(deferred[d].node)] = node, owners[size_t(deferred[d].node)] = {&part, 0};
      } else {
        tree.nodes.push_back(node), owners.push_back({&part, i});
      }
    }
    tree.depth = std::max(tree.depth, part.depth);
    tree.splits += part.splits;
  }
  std::vector<Source> sources;
  for (size_t i = 0; i < tree.nodes.size(); ++i) {
    const Part& part = *owners[i].part;
    const BspNode& local = part.nodes[owners[i].node];
    tree.nodes[i].first = uint32_t(sources.size());
    for (uint32_t k = local.first; k < local.first + local.count; ++k) {
      tree.node_polygons.push_back(uint32_t(sources.size()));
      sources.push_back({&part.frags, part.node_polygons[k]});
    }
  }
  tree.fragments = assemble(soup, sources, threads);
}

// Splits leave T-junctions between a polygon's fragments; they are closed so that the seams
// rasterize without cracks (docs/accuracy.md, "Specks"). Only fragments of one source polygon meet
// at such seams, so the split polygons are closed in kSeamChunks fixed ranges of ids, in parallel,
// and copied back in place.
constexpr size_t kSeamChunks = 16;

void close_seams(BspTree& tree, const CancelToken* cancel, unsigned threads) {
  const PolygonSoup& frags = tree.fragments;
  uint32_t ids = 0;
  for (const Polygon& p : frags.polygons) ids = std::max(ids, p.id + 1);
  std::vector<uint32_t> per_id(ids, 0);
  for (const Polygon& p : frags.polygons) ++per_id[p.id];
  std::vector<std::vector<uint32_t>> members(kSeamChunks);
  for (uint32_t i = 0; i < frags.polygons.size(); ++i) {
    const uint32_t id = frags.polygons[i].id;
    if (per_id[id] >= 2) members[size_t(id) * kSeamChunks / ids].push_back(i);
  }
  std::vector<PolygonSoup> closed(kSeamChunks);
  run_tasks(threads, kSeamChunks, [&](size_t c) {
    closed[c] = make_fragment_soup(frags);
    for (uint32_t i : members[c]) append_polygon(closed[c], frags, frags.polygons[i]);
    close_t_junctions(closed[c], tree.epsilon, cancel);
  });
  std::vector<Source> sources(frags.polygons.size());
  for (uint32_t i = 0; i < frags.polygons.size(); ++i) sources[i] = {&frags, i};
  for (size_t c = 0; c < kSeamChunks; ++c) {
    for (size_t k = 0; k < members[c].size(); ++k) sources[members[c][k]] = {&closed[c], uint32_t(k)};
  }
  tree.fragments = assemble(frags, sources, threads);
}

// Bounds bottom-up: children always have larger indices than their parent.
void compute_bounds(BspTree& tree, CancelMeter& meter) {
  const PolygonSoup& kept = tree.fragments;
  for (size_t i = tree.nodes.size(); i-- > 0;) {
    BspNode& node = tree.nodes[i];
    meter.add(1 + node.count);
    node.lo = Vec3(std::numeric_limits<double>::infinity());
    node.hi = -node.lo;
    for (uint32_t k = node.first; k < node.first + node.count; ++k) {
      for (const Vec3& p : kept.points(kept.polygons[tree.node_polygons[k]])) grow(node.lo, node.hi, p);
    }
    for (int32_t child : {node.front, node.back}) {
      if (child < 0) continue;
      node.lo = glm::min(node.lo, tree.nodes[size_t(child)].lo);
      node.hi = glm::max(node.hi, tree.nodes[size_t(child)].hi);
    }
  }
}

}  // namespace

BspTree build_bsp(const PolygonSoup& soup, const BspOptions& options, const CancelToken* cancel, unsigned threads) {
  Stopwatch clock;
  BspTree tree;
  tree.input_polygons = soup.polygons.size();
  tree.epsilon = scene_epsilon(soup, options.epsilon);
  Part top;
  top.frags = make_fragment_soup(soup);
  top.frags.positions.reserve(soup.positions.size());
  top.frags.normals.reserve(soup.normals.size());
  top.frags.polygons.reserve(soup.polygons.size());
  CancelMeter meter(cancel, kClassificationsPerCheck);
  std::vector<uint32_t> all;
  all.reserve(soup.polygons.size());
  for (const Polygon& p : soup.polygons) {
    meter.add(1);
    all.push_back(append_polygon(top.frags, soup, p));
  }
  if (all.empty()) {
    tree.fragments = std::move(top.frags);
    tree.build_ms = clock.elapsed_ms();
    return tree;
  }
  top.nodes.emplace_back();
  Builder builder(top, options, tree.epsilon, cancel,
                  std::max(all.size() / kSubtreesPerThreadedBuild, kMinParallelSubtree));
  builder.run(0, all, 1);
  const std::vector<Part> parts = build_deferred(top, builder.deferred(), options, tree.epsilon, cancel, threads);
  splice(tree, top, builder.deferred(), parts, soup, threads);
  close_seams(tree, cancel, threads);
  compute_bounds(tree, meter);
  tree.build_ms = clock.elapsed_ms();
  return tree;
}

}  // namespace rr
