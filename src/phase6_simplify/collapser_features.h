#pragma once
// Phase VI, steps 0 to 4 (collapser.h): the triangles around each vertex,
// the quadrics, what the planes around a vertex say of it (flat, a crease,
// a corner), each vertex's kind, and the planes along open boundaries.
// Included by collapser.h, at its end.

namespace recon::simplification_steps {

template <class Queue, Loop loop>
void Collapser<Queue, loop>::load_triangles(const Mesh& mesh) {
  tris_.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) tris_.push_back(t);
  faces_.resize(p_.size());
  const auto parts = static_cast<std::size_t>(std::max(1, thread_count()));
  detail::parallel_for(parts, [&](std::size_t part) {
    const std::size_t lo = part * p_.size() / parts, hi = (part + 1) * p_.size() / parts;
    std::vector<std::uint32_t> degree(hi - lo, 0);
    for (const auto& t : tris_)
      for (const std::uint32_t v : t)
        if (v >= lo && v < hi) ++degree[v - lo];
    for (std::size_t v = lo; v < hi; ++v) faces_[v].reserve(degree[v - lo]);
    for (std::uint32_t f = 0; f < tris_.size(); ++f)
      for (const std::uint32_t v : tris_[f])
        if (v >= lo && v < hi) faces_[v].push_back(f);
  });
  alive_tri_.assign(tris_.size(), 1);
  s_.triangles = tris_.size();
  if (loop == Loop::fast) rings_.assign(p_.size(), RingMemo{});
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::build_quadrics() {
  struct Plane {
    Vec3 n;
    double d, w;  // w = 0: no area, no plane
  };
  std::vector<Plane> planes(tris_.size());
  detail::parallel_for(tris_.size(), [&](std::size_t t) {
    const auto& f = tris_[t];
    const Vec3 n2 = cross_of(p_[f[0]], p_[f[1]], p_[f[2]]);
    const double twice_area = n2.norm();
    if (!(twice_area > 0.0)) {
      planes[t] = {Vec3::Zero(), 0.0, 0.0};
      return;
    }
    const Vec3 n = n2 / twice_area;
    planes[t] = {n, -n.dot(p_[f[0]]), 0.5 * twice_area};
  });
  q_.assign(p_.size(), {});
  detail::parallel_for(p_.size(), [&](std::size_t v) {
    for (const std::uint32_t f : faces_[v])
      if (planes[f].w > 0.0) q_[v].add_plane(planes[f].n, planes[f].d, planes[f].w);
  });
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::shape_of_planes() {
  plane_shape_.assign(p_.size(), flat);
  crease_direction_.assign(p_.size(), Vec3::Zero());
  detail::parallel_for_dynamic(p_.size(), 4096, [&](std::size_t i) {  // each vertex alone: any threads
    const auto v = static_cast<std::uint32_t>(i);
    const Quadric& q = q_[v];
    if (!(q.weight > 0.0) || planar_fan(v)) return;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(moment_of(q));
    const Vec3 lambda = solver.eigenvalues();  // ascending
    if (lambda[0] > third_direction) {
      plane_shape_[v] = corner;
    } else if (lambda[1] > second_direction) {
      plane_shape_[v] = crease;
      crease_direction_[v] = solver.eigenvectors().col(0);
    }
  });
  confirm_corners();
  drop_off_line_creases();
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::drop_off_line_creases() {
  std::vector<std::uint32_t> off;
  for (std::uint32_t v = 0; v < p_.size(); ++v)
    if (plane_shape_[v] == crease && !on_line(v)) off.push_back(v);
  for (const std::uint32_t v : off) plane_shape_[v] = flat;
}

template <class Queue, Loop loop>
bool Collapser<Queue, loop>::on_line(std::uint32_t v) {
  neighbours(v, ring_);
  std::erase_if(ring_, [&](std::uint32_t w) { return !crease_edge(v, w); });
  for (std::size_t i = 0; i < ring_.size(); ++i)
    for (std::size_t j = i + 1; j < ring_.size(); ++j) {
      const Vec3 a = p_[ring_[i]], ab = p_[ring_[j]] - a, av = p_[v] - a;
      if (!(ab.squaredNorm() > 0.0)) continue;
      const double t = av.dot(ab) / ab.squaredNorm();
      if (t > 0.0 && t < 1.0 && (av - t * ab).norm() <= line_tolerance * ab.norm()) return true;
    }
  return false;
}

template <class Queue, Loop loop>
Eigen::Matrix3d Collapser<Queue, loop>::moment_of(const Quadric& q) {
  Eigen::Matrix3d a;
  a << q.xx, q.xy, q.xz, q.xy, q.yy, q.yz, q.xz, q.yz, q.zz;
  return a / q.weight;
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::confirm_corners() {
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t v = 0; v < p_.size(); ++v)
    if (plane_shape_[v] != flat) candidates.push_back(v);
  std::vector<std::uint32_t> index(p_.size(), none);  // per vertex: its place in candidates
  for (std::uint32_t i = 0; i < candidates.size(); ++i) index[candidates[i]] = i;
  UnionFind clusters(candidates.size());
  std::vector<Quadric> wide(candidates.size());
  std::vector<std::uint8_t> confirmed(candidates.size(), 0);
  std::vector<Vec3> meet(candidates.size(), Vec3::Zero());
  std::vector<double> strength(candidates.size(), 0.0);  // the ball's third eigenvalue
  for (std::uint32_t i = 0; i < candidates.size(); ++i) {
    const std::uint32_t v = candidates[i];
    wide[i] = planes_in_ball(v, ball_);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(moment_of(wide[i]));
    if (!(solver.eigenvalues()[0] > third_direction_wide)) {
      demote_by_wide_planes(v, solver);
      continue;
    }
    confirmed[i] = 1;
    meet[i] = meeting_point(wide[i]);
    strength[i] = solver.eigenvalues()[0];
    // A confirmed candidate in the ball whose planes meet at the same
    // point (within v's mean edge): the same corner.
    const double same = mean_edge(v);
    for (const std::uint32_t w : ball_) {
      const std::uint32_t j = index[w];
      if (j != none && j < i && confirmed[j] && (meet[j] - meet[i]).norm() <= same) clusters.unite(i, j);
    }
  }
  keep_one_per_cluster(candidates, confirmed, clusters, wide, strength);
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::demote_by_wide_planes(std::uint32_t v,
                                                   const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>& wide) {
  if (wide.eigenvalues()[1] > second_direction) {
    plane_shape_[v] = crease;
    crease_direction_[v] = wide.eigenvectors().col(0);
  } else {
    plane_shape_[v] = flat;
  }
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::keep_one_per_cluster(const std::vector<std::uint32_t>& candidates,
                                                  const std::vector<std::uint8_t>& confirmed, UnionFind& clusters,
                                                  const std::vector<Quadric>& wide,
                                                  const std::vector<double>& strength) {
  const std::size_t n = candidates.size();
  std::vector<std::uint32_t> root(n, none);
  std::vector<Quadric> planes(n);  // per root: its cluster's planes
  for (std::uint32_t i = 0; i < n; ++i)
    if (confirmed[i]) {
      root[i] = clusters.find(i);
      planes[root[i]] += wide[i];
    }
  std::vector<double> strongest(n, 0.0);  // per root: its members' largest third eigenvalue
  for (std::uint32_t i = 0; i < n; ++i)
    if (root[i] != none) strongest[root[i]] = std::max(strongest[root[i]], strength[i]);
  for (std::uint32_t i = 0; i < n; ++i)
    if (root[i] != none && !(strongest[root[i]] > corner_strength)) {
      demote_by_wide_planes(candidates[i], Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(moment_of(wide[i])));
      root[i] = none;
    }
  std::vector<std::uint32_t> keeper(n, none);  // per root: the candidate kept
  for (std::uint32_t i = 0; i < n; ++i) {
    if (root[i] == none) continue;
    const Vec3 meet = meeting_point(planes[root[i]]);
    std::uint32_t& k = keeper[root[i]];
    if (k == none || (p_[candidates[i]] - meet).squaredNorm() < (p_[candidates[k]] - meet).squaredNorm()) k = i;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    if (root[i] == none) continue;
    if (keeper[root[i]] == i) {
      plane_shape_[candidates[i]] = corner;
      continue;
    }
    const Vec3 line = p_[candidates[i]] - p_[candidates[keeper[root[i]]]];
    plane_shape_[candidates[i]] = crease;
    crease_direction_[candidates[i]] = line.norm() > 0.0 ? Vec3(line.normalized()) : Vec3::UnitX();
  }
}

template <class Queue, Loop loop>
double Collapser<Queue, loop>::mean_edge(std::uint32_t v) {
  neighbours(v, ring_);
  double sum = 0.0;
  for (const std::uint32_t w : ring_) sum += (p_[w] - p_[v]).norm();
  return ring_.empty() ? 0.0 : sum / static_cast<double>(ring_.size());
}

template <class Queue, Loop loop>
Vec3 Collapser<Queue, loop>::meeting_point(const Quadric& q) {
  Eigen::Matrix3d a;
  a << q.xx, q.xy, q.xz, q.xy, q.yy, q.yz, q.xz, q.yz, q.zz;
  return a.ldlt().solve(-Vec3(q.x, q.y, q.z));
}

template <class Queue, Loop loop>
Quadric Collapser<Queue, loop>::planes_in_ball(std::uint32_t v, std::vector<std::uint32_t>& inside) {
  const double reach = corner_reach * mean_edge(v);
  const double reach2 = reach * reach;
  inside.assign(1, v);
  seen_.resize(p_.size(), 0);
  seen_[v] = 1;
  Quadric q;
  for (std::size_t next = 0; next < inside.size(); ++next)
    for (const std::uint32_t f : faces_[inside[next]])
      for (const std::uint32_t w : tris_[f])
        if (!seen_[w] && (p_[w] - p_[v]).squaredNorm() <= reach2) {
          seen_[w] = 1;
          inside.push_back(w);
        }
  counted_.clear();
  counted_face_.resize(tris_.size(), 0);
  for (const std::uint32_t w : inside)
    for (const std::uint32_t f : faces_[w])
      if (!counted_face_[f]) {
        counted_face_[f] = 1;
        counted_.push_back(f);
      }
  for (const std::uint32_t f : counted_) {
    counted_face_[f] = 0;
    const Vec3 n2 = normal(f);
    const double twice_area = n2.norm();
    if (twice_area > 0.0) q.add_plane(n2 / twice_area, -n2.dot(p_[tris_[f][0]]) / twice_area, 0.5 * twice_area);
  }
  for (const std::uint32_t w : inside) seen_[w] = 0;
  return q;
}

template <class Queue, Loop loop>
bool Collapser<Queue, loop>::planar_fan(std::uint32_t v) const {
  if (faces_[v].empty()) return true;
  const Vec3 first = normal(faces_[v][0]).normalized();
  for (const std::uint32_t f : faces_[v])
    if (normal(f).normalized().dot(first) < 0.985) return false;
  return true;
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::find_features() {
  shape_of_planes();
  kind_.assign(p_.size(), free_vertex);
  std::vector<std::uint8_t> open(p_.size(), 0);
  each_on_all_threads(p_.size(), std::identity{}, [&](std::uint32_t a, std::vector<std::uint32_t>& ring) {
    keep_ring(a, ring);
    kind_[a] = kind_of(a, ring, open[a]);
  });
  for (std::uint32_t a = 0; a < p_.size(); ++a) {
    if (!open[a]) continue;
    neighbours(a, ring_);
    for (const std::uint32_t b : ring_)
      if (b > a && faces_on(a, b).second == 1) boundary_edges_.push_back({a, b});
  }
  kind0_ = kind_;
}

template <class Queue, Loop loop>
std::uint8_t Collapser<Queue, loop>::kind_of(std::uint32_t a, std::vector<std::uint32_t>& ring,
                                             std::uint8_t& open) const {
  neighbours(a, ring);
  std::size_t boundary = 0;
  bool non_manifold = false;
  for (const std::uint32_t b : ring) {
    const std::size_t n = faces_on(a, b).second;
    boundary += n == 1 ? 1 : 0;
    non_manifold = non_manifold || n > 2;
  }
  open = boundary > 0 ? 1 : 0;
  const PlaneShape shape = static_cast<PlaneShape>(plane_shape_[a]);
  if (non_manifold || shape == corner || (boundary > 0 && (boundary != 2 || shape != flat))) return fixed_vertex;
  if (boundary == 2 || shape == crease) return line_vertex;
  return free_vertex;
}

template <class Queue, Loop loop>
bool Collapser<Queue, loop>::along_crease(std::uint32_t a, std::uint32_t b) const {
  if (plane_shape_[a] == corner) return true;
  if (plane_shape_[a] == flat) return false;
  const Vec3 e = p_[b] - p_[a];
  return std::abs(crease_direction_[a].dot(e)) > 0.82 * e.norm();
}

template <class Queue, Loop loop>
void Collapser<Queue, loop>::add_boundary_planes() {
  for (const auto& [a, b] : boundary_edges_) {
    const std::uint32_t f = faces_on(a, b).first;
    const Vec3 along = p_[b] - p_[a];
    Vec3 m = along.cross(normal(f));
    if (!(m.norm() > 0.0)) continue;
    m.normalize();
    const double w = along.squaredNorm();
    q_[a].add_plane(m, -m.dot(p_[a]), w);
    q_[b].add_plane(m, -m.dot(p_[a]), w);
  }
}

}  // namespace recon::simplification_steps
