#pragma once
// Phase VI, step 5 (collapser.h): whether a move is allowed (the link
// condition, lines, folds, the error bound), the collapse itself, and the
// loops that run it.
// Included by collapser.h, at its end.

namespace recon::simplification_steps {

template <class Queue, Loop loop>
void Collapser<Queue, loop>::run(std::size_t may_remove) {
  for (std::uint32_t v = 0; v < p_.size(); ++v)
    if (mine(v)) requeue(v);
  collapse_cheapest(may_remove, std::numeric_limits<std::size_t>::max(), std::numeric_limits<double>::infinity());
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::run_below(double limit, std::size_t most, const std::vector<double>& cost) {
  for (const std::uint32_t v : members_)
    if (mine(v) && cost[v] <= limit) requeue(v);
  collapse_cheapest(std::numeric_limits<std::size_t>::max(), most, limit);
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::costs_now(std::vector<double>& out) {
  out.assign(p_.size(), std::numeric_limits<double>::infinity());
  const std::vector<std::uint32_t>& living = s_.living;
  const auto at = [&](std::size_t i) { return living[i]; };
  each_on_all_threads(living.size(), at, [&](std::uint32_t v, std::vector<std::uint32_t>& scratch) {
    if (!fresh_[v]) {
      keep_ring(v, scratch);
      const auto c = cheapest(v, scratch);
      out[v] = c.second;
      if (loop == Loop::plain) return;
      cheap_[v] = c;
      fresh_[v] = 1;
    }
    out[v] = cheap_[v].second;
  });
}

template <class Queue, Loop loop>
template <class At, class Body>
void Collapser<Queue, loop>::each_on_all_threads(std::size_t count, At at, Body body) {
  on_all_threads_ = true;
  constexpr std::size_t block = 4096;
  detail::parallel_for_dynamic((count + block - 1) / block, 1, [&](std::size_t b) {
    std::vector<std::uint32_t> scratch;
    for (std::size_t i = b * block; i < std::min(count, (b + 1) * block); ++i)
      body(static_cast<std::uint32_t>(at(i)), scratch);
  });
  on_all_threads_ = false;
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::collapse_cheapest(std::size_t may_remove, std::size_t most, double limit) {
  while (removed_ < may_remove && collapses_ < most && !queue_.empty()) {
    const std::uint32_t u = vertex_at(queue_.pop(counts_));
    if (key_[u] > limit) break;  // and every key after it
    const std::uint32_t v = best_[u];
    if (allowed(u, v)) {
      collapse(u, v);
      ++collapses_;
      continue;
    }
    ++refused_;
    retry(u);
  }
}

template <class Queue, Loop loop>
Mesh Collapser<Queue, loop>::result(const Mesh& mesh, Simplification& out) const {
  out.crease_vertices = static_cast<std::size_t>(std::count(kind0_.begin(), kind0_.end(), line_vertex));
  out.corner_vertices = static_cast<std::size_t>(std::count(kind0_.begin(), kind0_.end(), fixed_vertex));
  Mesh m;
  std::vector<std::uint32_t> index(p_.size(), none);
  for (std::size_t t = 0; t < tris_.size(); ++t)
    if (alive_tri_[t])
      for (const std::uint32_t v : tris_[t]) index[v] = 0;
  for (std::uint32_t v = 0; v < p_.size(); ++v) {
    if (index[v] == none) continue;
    index[v] = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back(p_[v]);
    if (mesh.has_colors()) m.colors.push_back(mesh.colors[v]);
    if (mesh.has_normals()) m.normals.push_back(mesh.normals[v]);
  }
  for (std::size_t t = 0; t < tris_.size(); ++t)
    if (alive_tri_[t]) m.triangles.push_back({index[tris_[t][0]], index[tris_[t][1]], index[tris_[t][2]]});
  return m;
}

template <class Queue, Loop loop>
bool Collapser<Queue, loop>::link_holds(std::uint32_t u, std::uint32_t v) {
  neighbours(u, ring_);
  neighbours(v, ring2_);
  std::size_t shared = 0;
  for (std::size_t i = 0, j = 0; i < ring_.size() && j < ring2_.size();) {
    if (ring_[i] < ring2_[j]) {
      ++i;
    } else if (ring2_[j] < ring_[i]) {
      ++j;
    } else {
      ++shared, ++i, ++j;
    }
  }
  std::size_t far = 0;
  for (const std::uint32_t f : faces_[u])
    if (has(f, v)) ++far;
  return far > 0 && shared == far;
}

template <class Queue, Loop loop>
bool Collapser<Queue, loop>::lines_stay(std::uint32_t u, std::uint32_t v) {
  if (kind_[u] != line_vertex || plane_shape_[u] != flat || faces_on(u, v).second != 1) return true;
  neighbours(u, ring_);
  for (const std::uint32_t w : ring_)
    if (w != v && faces_on(u, w).second == 1 && faces_on(v, w).second == 1) return false;
  return true;
}

template <class Queue, Loop loop>
bool Collapser<Queue, loop>::no_fold(std::uint32_t u, std::uint32_t v) const {
  Vec3 fan = Vec3::Zero();
  for (const std::uint32_t f : faces_[u]) fan += normal(f);
  for (const std::uint32_t f : faces_[u]) {
    if (has(f, v)) continue;
    const Vec3 before = normal(f);
    std::array<Vec3, 3> c{};
    for (std::size_t i = 0; i < 3; ++i) c[i] = tris_[f][i] == u ? p_[v] : p_[tris_[f][i]];
    const Vec3 after = (c[1] - c[0]).cross(c[2] - c[0]);
    const double scale = (c[1] - c[0]).squaredNorm() + (c[2] - c[1]).squaredNorm() + (c[0] - c[2]).squaredNorm();
    if (!(after.norm() > 1e-10 * scale)) return false;
    // A sliver's normal (three vertices nearly in a row, as along phase
    // V's creases) says nothing: only a real triangle's turn is checked.
    const double scale_before = (p_[tris_[f][1]] - p_[tris_[f][0]]).squaredNorm() +
                                (p_[tris_[f][2]] - p_[tris_[f][1]]).squaredNorm() +
                                (p_[tris_[f][0]] - p_[tris_[f][2]]).squaredNorm();
    const bool sliver = before.norm() < sliver_ratio * scale_before;
    if (!sliver && before.dot(after) < cos_turn_ * before.norm() * after.norm()) return false;
    // A sliver may turn, but not fold over: it must still face the side
    // u's triangles face together.
    if (sliver && !(fan.dot(after) > 0.0)) return false;
    // Nor may a real triangle become a sliver: its normal would say
    // nothing more, and it could stand across the surface (a sharp edge
    // in the middle of a face).
    if (!sliver && after.norm() < sliver_ratio * scale) return false;
    if (duplicates(f, u, v)) return false;
  }
  return true;
}

template <class Queue, Loop loop>
bool Collapser<Queue, loop>::duplicates(std::uint32_t f, std::uint32_t u, std::uint32_t v) const {
  std::uint32_t a = none, b = none;
  for (const std::uint32_t w : tris_[f])
    if (w != u) (a == none ? a : b) = w;
  for (const std::uint32_t g : faces_[v])
    if (has(g, a) && has(g, b)) return true;
  return false;
}

template <class Queue, Loop loop>
bool Collapser<Queue, loop>::within_bound(std::uint32_t u, std::uint32_t v) {
  if (kept_.empty()) return true;
  handed_.clear();
  handed_.push_back(u);
  for (const std::uint32_t f : faces_[u]) handed_.insert(handed_.end(), kept_[f].begin(), kept_[f].end());
  keepers_.clear();
  for (const std::uint32_t f : faces_[u])
    if (!has(f, v)) keepers_.push_back(f);
  nearest_.clear();
  for (const std::uint32_t x : handed_) {
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t keeper = none;
    for (const std::uint32_t f : keepers_) {
      const auto& t = tris_[f];
      const auto at = [&](std::uint32_t w) -> const Vec3& { return w == u ? p_[v] : p_[w]; };
      const double d = point_triangle_distance(p_[x], at(t[0]), at(t[1]), at(t[2]));
      if (d < best) best = d, keeper = f;
    }
    if (!(best <= options_.max_error)) return false;
    nearest_.push_back({keeper, best});
  }
  return true;
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::collapse(std::uint32_t u, std::uint32_t v) {
  if (!kept_.empty()) hand_over(u);
  for (const std::uint32_t f : faces_[u])
    for (const std::uint32_t w : tris_[f]) {
      fresh_[w] = 0;
      if (!rings_.empty()) rings_[w].size = RingMemo::stale;
      prefetch_quadric(w);
    }
  for (const std::uint32_t f : faces_[u]) {
    if (has(f, v)) {
      remove_triangle(f, u);
    } else {
      for (std::uint32_t& w : tris_[f])
        if (w == u) w = v;
      faces_[v].push_back(f);
    }
  }
  faces_[u].clear();
  q_[v] += q_[u];
  kind_[u] = fixed_vertex;
  queue_.erase(id(u));
  requeue_around(v);
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::requeue_around(std::uint32_t v) {
  if constexpr (loop == Loop::plain) {
    neighbours(v, around_);
    if (mine(v)) requeue(v);
    for (const std::uint32_t w : around_)
      if (mine(w)) requeue(w);
  } else {
    prefetch_stale_around(v);
    if (mine(v)) requeue(v);
    for (const std::uint32_t f : faces_[v])
      for (const std::uint32_t w : tris_[f])
        if (w != v && mine(w)) requeue(w);
  }
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::prefetch_quadric(std::uint32_t w) const {
  const auto* bytes = reinterpret_cast<const char*>(&q_[w]);
  __builtin_prefetch(bytes);
  __builtin_prefetch(bytes + sizeof(Quadric) - 1);
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::prefetch_stale_around(std::uint32_t v) const {
  const auto for_stale = [&](auto&& visit) {
    for (const std::uint32_t f : faces_[v])
      for (const std::uint32_t w : tris_[f])
        if (mine(w) && !fresh_[w]) visit(w);  // (another block's lists may be changing)
  };
  for_stale([&](std::uint32_t w) { __builtin_prefetch(faces_[w].data()); });
  for_stale([&](std::uint32_t w) {
    for (const std::uint32_t g : faces_[w]) __builtin_prefetch(&tris_[g]);
  });
  for_stale([&](std::uint32_t w) {
    for (const std::uint32_t g : faces_[w])
      for (const std::uint32_t x : tris_[g]) __builtin_prefetch(&p_[x]);
  });
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::hand_over(std::uint32_t u) {  // before u's triangles change
  for (const std::uint32_t f : faces_[u]) kept_[f].clear();
  for (std::size_t i = 0; i < handed_.size(); ++i) {
    kept_[nearest_[i].first].push_back(handed_[i]);
    vertex_error_ = std::max(vertex_error_, nearest_[i].second);
  }
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::remove_triangle(std::uint32_t f, std::uint32_t u) {
  alive_tri_[f] = 0;
  ++removed_;
  for (const std::uint32_t w : tris_[f]) {
    if (w == u) continue;
    auto& list = faces_[w];
    list.erase(std::find(list.begin(), list.end(), f));
  }
}

}  // namespace recon::simplification_steps
