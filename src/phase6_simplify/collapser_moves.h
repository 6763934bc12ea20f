#pragma once
// Phase VI (collapser.h): the small queries on the mesh, the rings, the
// moves a vertex may make by the feature rules and their costs, and the
// queue of cheapest moves.
// Included by collapser.h, at its end.

namespace recon::simplification_steps {

template <class Queue, Loop loop>
std::uint32_t Collapser<Queue, loop>::third(std::uint32_t f, std::uint32_t a, std::uint32_t b) const {
  for (const std::uint32_t v : tris_[f])
    if (v != a && v != b) return v;
  return none;
}

template <class Queue, Loop loop>
std::pair<std::uint32_t, std::size_t> Collapser<Queue, loop>::faces_on(std::uint32_t a, std::uint32_t b) const {
  std::pair<std::uint32_t, std::size_t> r{none, 0};
  for (const std::uint32_t f : faces_[a])
    if (has(f, b)) {
      if (r.second == 0) r.first = f;
      ++r.second;
    }
  return r;
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const {
  if (rings_.empty()) return gather_ring(v, out);
  RingMemo& memo = rings_[v];
  if (memo.size <= memo.ring.size()) {
    out.assign(memo.ring.begin(), memo.ring.begin() + memo.size);
    return;
  }
  gather_ring(v, out);
  if (out.size() > memo.ring.size() || on_all_threads_) return;
  std::copy(out.begin(), out.end(), memo.ring.begin());
  memo.size = static_cast<std::uint32_t>(out.size());
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::keep_ring(std::uint32_t v, std::vector<std::uint32_t>& scratch) const {
  if (rings_.empty()) return;
  RingMemo& memo = rings_[v];
  if (memo.size <= memo.ring.size()) return;
  gather_ring(v, scratch);
  if (scratch.size() > memo.ring.size()) return;
  std::copy(scratch.begin(), scratch.end(), memo.ring.begin());
  memo.size = static_cast<std::uint32_t>(scratch.size());
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::gather_ring(std::uint32_t v, std::vector<std::uint32_t>& out) const {
  out.clear();
  for (const std::uint32_t f : faces_[v])
    for (const std::uint32_t w : tris_[f]) {
      if (w == v) continue;
      std::size_t i = out.size();
      while (i > 0 && out[i - 1] > w) --i;
      if (i > 0 && out[i - 1] == w) continue;
      out.push_back(w);
      for (std::size_t j = out.size() - 1; j > i; --j) out[j] = out[j - 1];
      out[i] = w;
    }
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::moves(std::uint32_t u, std::vector<std::uint32_t>& out) const {
  out.clear();
  if (kind_[u] == fixed_vertex) return;
  neighbours(u, out);
  if (kind_[u] == free_vertex) return;
  const bool on_boundary = plane_shape_[u] == flat;
  std::erase_if(out, [&](std::uint32_t v) { return on_boundary ? faces_on(u, v).second != 1 : !crease_edge(u, v); });
}

template <class Queue, Loop loop>
std::pair<std::uint32_t, double> Collapser<Queue, loop>::cheapest(std::uint32_t u,
                                                                  std::vector<std::uint32_t>& scratch) const {
  moves(u, scratch);
  double best = std::numeric_limits<double>::infinity();
  std::uint32_t to = none;
  for (const std::uint32_t v : scratch) {
    const double c = cost(u, v);
    if (c < best) best = c, to = v;
  }
  return {to, best};
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::first_costs() {
  cheap_.assign(p_.size(), {none, 0.0});
  fresh_.assign(p_.size(), 0);
  if constexpr (loop == Loop::plain) return;
  each_on_all_threads(p_.size(), std::identity{}, [&](std::uint32_t v, std::vector<std::uint32_t>& scratch) {
    keep_ring(v, scratch);
    cheap_[v] = cheapest(v, scratch);
    fresh_[v] = 1;
  });
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::requeue(std::uint32_t u) {
  if (!fresh_[u]) {
    cheap_[u] = cheapest(u, moves_);
    fresh_[u] = loop == Loop::fast;
  }
  place(u, cheap_[u].first, cheap_[u].second);
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::retry(std::uint32_t u) {
  moves(u, moves_);
  ranked_.clear();
  for (const std::uint32_t v : moves_) ranked_.emplace_back(cost(u, v), v);
  std::sort(ranked_.begin(), ranked_.end());
  for (const auto& [c, v] : ranked_)
    if (allowed(u, v)) {
      best_[u] = v;
      key_[u] = c;
      queue_.set(id(u), c, counts_);
      return;
    }
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::place(std::uint32_t u, std::uint32_t to, double c) {
  if (to == none) {
    best_[u] = to;
    queue_.erase(id(u));
    return;
  }
  if (loop == Loop::fast && best_[u] == to && key_[u] == c && queue_.contains(id(u))) return;
  best_[u] = to;
  key_[u] = c;
  queue_.set(id(u), c, counts_);
}

}  // namespace recon::simplification_steps
