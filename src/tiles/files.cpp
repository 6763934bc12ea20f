// The files of a tiled run (tiles/files.h): each written whole with a
// checksum (binary_file.h), each read back with every count and index
// checked against what it may name, so that a damaged or foreign file is a
// ParseError naming it, never a crash or a silently wrong mesh. Only
// binary_file.cpp and zlib behind it: the fuzz target for these readers
// (fuzz/tile_files.cpp) builds them alone.
#include "tiles/files.h"

#include "recon/core/errors.h"

#include <cmath>
#include <set>

namespace recon::tile_files {

namespace {

ParseError bad(const detail::BinaryReader& in, const std::string& what) {
  return ParseError(in.path().string() + ": " + what);
}

std::string at_record(const char* kind, std::size_t i) { return std::string(kind) + " " + std::to_string(i) + ": "; }

}  // namespace

// ---------------------------------------------------------------------------
// Step 1's points and colours (written by the binning, tiles/step1_plan.cpp).

std::vector<PointRecord> read_point_records(const std::filesystem::path& path) {
  detail::BinaryReader in(path, points_magic);
  std::vector<PointRecord> records = in.get_rest<PointRecord>();
  for (std::size_t i = 0; i < records.size(); ++i)
    if (!std::isfinite(records[i].x) || !std::isfinite(records[i].y) || !std::isfinite(records[i].z))
      throw bad(in, at_record("point", i) + "a coordinate is not a finite number");
  return records;
}

std::vector<Color> read_colors(const std::filesystem::path& path) {
  return detail::BinaryReader(path, colors_magic).get_rest<Color>();
}

// ---------------------------------------------------------------------------
// Step 2's orientation (tile-N.orient).

void write_orientation(const std::filesystem::path& path, const Orientation& o) {
  detail::BinaryWriter out(path, orient_magic);
  out.put_vector<std::int8_t>(o.sign);
  out.put_vector<std::uint32_t>(o.piece);
  out.put_vector<PieceTop>(o.tops);
  out.put_vector<BorderRecord>(o.border);
  out.put_vector<DipoleRecord>(o.dipoles);
  out.put(o.inexact);
  out.commit();
}

Orientation read_orientation(const std::filesystem::path& path) {
  detail::BinaryReader in(path, orient_magic);
  Orientation o;
  o.sign = in.get_vector<std::int8_t>();
  o.piece = in.get_vector<std::uint32_t>();
  o.tops = in.get_vector<PieceTop>();
  o.border = in.get_vector<BorderRecord>();
  o.dipoles = in.get_vector<DipoleRecord>();
  o.inexact = in.get<std::uint64_t>();
  in.finish();
  if (o.sign.size() != o.piece.size())
    throw bad(in, std::to_string(o.sign.size()) + " signs for " + std::to_string(o.piece.size()) + " pieces' points");
  if (o.tops.size() >= none) throw bad(in, "more pieces than a tile can hold");
  for (std::size_t i = 0; i < o.sign.size(); ++i) {
    if (o.sign[i] != 1 && o.sign[i] != -1) throw bad(in, at_record("point", i) + "a sign other than +1 or -1");
    if (o.piece[i] >= o.tops.size()) throw bad(in, at_record("point", i) + "names a piece the tile does not have");
  }
  for (std::size_t i = 0; i < o.tops.size(); ++i)
    if (std::isnan(o.tops[i].z)) throw bad(in, at_record("piece", i) + "its highest sample's height is not a number");
  for (std::size_t i = 0; i < o.border.size(); ++i) {
    const BorderRecord& b = o.border[i];
    if (b.node >= o.tops.size()) throw bad(in, at_record("border sample", i) + "names a piece the tile does not have");
    if (!std::isfinite(b.normal[0]) || !std::isfinite(b.normal[1]) || !std::isfinite(b.normal[2]))
      throw bad(in, at_record("border sample", i) + "its normal is not finite");
  }
  for (std::size_t i = 0; i < o.dipoles.size(); ++i) {
    const DipoleRecord& d = o.dipoles[i];
    if (d.piece >= o.tops.size()) throw bad(in, at_record("core sample", i) + "names a piece the tile does not have");
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(d.origin[a]) || !std::isfinite(d.area_normal[a]))
        throw bad(in, at_record("core sample", i) + "its origin or normal is not finite");
  }
  return o;
}

// ---------------------------------------------------------------------------
// Step 3's signs (flips.bin).

void write_flips(const std::filesystem::path& dir, const Flips& f) {
  detail::BinaryWriter out(flips(dir), flips_magic);
  out.put_vector<std::uint64_t>(f.first_node);
  out.put_vector<std::int8_t>(f.flip);
  out.put_vector<std::uint32_t>(f.object);
  out.commit();
}

Flips read_flips(const std::filesystem::path& dir) {
  detail::BinaryReader in(flips(dir), flips_magic);
  Flips f;
  f.first_node = in.get_vector<std::uint64_t>();
  f.flip = in.get_vector<std::int8_t>();
  f.object = in.get_vector<std::uint32_t>();
  in.finish();
  if (f.object.size() != f.flip.size())
    throw bad(in, std::to_string(f.object.size()) + " objects for " + std::to_string(f.flip.size()) + " pieces");
  for (std::size_t t = 0; t < f.first_node.size(); ++t)
    if (f.first_node[t] > f.flip.size() || (t > 0 && f.first_node[t] < f.first_node[t - 1]))
      throw bad(in, at_record("tile", t) + "its first piece is out of order or out of range");
  for (std::size_t i = 0; i < f.flip.size(); ++i) {
    if (f.flip[i] != 1 && f.flip[i] != -1) throw bad(in, at_record("piece", i) + "a sign other than +1 or -1");
    if (f.object[i] >= f.flip.size()) throw bad(in, at_record("piece", i) + "names an object that is no piece");
  }
  return f;
}

std::pair<std::uint64_t, std::uint64_t> Flips::pieces_of(std::size_t tile) const {
  const std::uint64_t end = tile + 1 < first_node.size() ? first_node[tile + 1] : flip.size();
  return {first_node[tile], end};
}

// ---------------------------------------------------------------------------
// Step 4's meshes (tile-N.mesh).

void write_mesh(const std::filesystem::path& path, const TileMesh& mesh) {
  detail::BinaryWriter out(path, mesh_magic);
  out.put_vector<MeshVertex>(mesh.vertices);
  out.put_vector<MeshTriangle>(mesh.triangles);
  out.put_vector<std::uint8_t>(mesh.peel_open);
  out.put_vector<std::uint64_t>(mesh.atom_triangles);
  out.put_vector<AtomVote>(mesh.votes);
  out.commit();
}

TileMesh read_mesh(const std::filesystem::path& path) {
  detail::BinaryReader in(path, mesh_magic);
  TileMesh m;
  m.vertices = in.get_vector<MeshVertex>();
  m.triangles = in.get_vector<MeshTriangle>();
  m.peel_open = in.get_vector<std::uint8_t>();
  m.atom_triangles = in.get_vector<std::uint64_t>();
  m.votes = in.get_vector<AtomVote>();
  in.finish();
  const std::size_t atoms = m.atom_triangles.size();
  if (m.vertices.size() >= none || atoms >= none || m.peel_open.size() >= none)
    throw bad(in, "more vertices, atoms or components than a tile can hold");
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const MeshVertex& v = m.vertices[i];
    if ((v.atom != none && v.atom >= atoms) || v.axis[0] > 3 || v.axis[1] > 3)
      throw bad(in, at_record("vertex", i) + "names an atom or an edge it cannot have");
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw bad(in, at_record("vertex", i) + "a coordinate is not a finite number");
    const Vec3 normal(static_cast<double>(v.normal[0]), static_cast<double>(v.normal[1]),
                      static_cast<double>(v.normal[2]));
    const double length = normal.norm();
    if (!std::isfinite(length) || !(length == 0.0 || std::abs(length - 1.0) < 1e-3))  // (no comparison with a NaN)
      throw bad(in, at_record("vertex", i) + "its normal is neither unit nor zero");
  }
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const MeshTriangle& t = m.triangles[i];
    if (t.v[0] >= m.vertices.size() || t.v[1] >= m.vertices.size() || t.v[2] >= m.vertices.size() ||
        (t.peel != none && t.peel >= m.peel_open.size()))
      throw bad(in, at_record("triangle", i) + "names a vertex or a component it does not have");
    const bool peelable = t.peel != none && !t.stray;  // (the stitch joins its vertices' atoms, tiles/step5_stitch.cpp)
    if (peelable &&
        (m.vertices[t.v[0]].atom == none || m.vertices[t.v[1]].atom == none || m.vertices[t.v[2]].atom == none))
      throw bad(in, at_record("triangle", i) + "a vertex of this peelable triangle has no atom");
  }
  for (std::size_t i = 0; i < m.votes.size(); ++i)
    if (m.votes[i].atom >= atoms) throw bad(in, at_record("vote", i) + "names an atom it does not have");
  return m;
}

// ---------------------------------------------------------------------------
// Step 1's plan (plan.bin).

namespace {

void put_vec(detail::BinaryWriter& out, const Vec3& v) {
  for (int a = 0; a < 3; ++a) out.put(v[a]);
}
Vec3 get_vec(detail::BinaryReader& in) {
  Vec3 v;
  for (int a = 0; a < 3; ++a) v[a] = in.get<double>();
  return v;
}
template <class T>
void put_optional(detail::BinaryWriter& out, const std::optional<T>& value) {
  out.put(static_cast<std::uint8_t>(value.has_value()));
  out.put(value.value_or(T{}));
}
template <class T>
std::optional<T> get_optional(detail::BinaryReader& in) {
  const bool has = in.get<std::uint8_t>() != 0;
  const T value = in.get<T>();
  return has ? std::optional<T>(value) : std::nullopt;
}

// What the steps index or divide by: the method, k, the lattice, the grid
// of tiles and each tile's place in it (ids name files: each once).
void check_plan(const detail::BinaryReader& in, const TilePlan& plan) {
  if (plan.method != Method::refined && plan.method != Method::hoppe92) throw bad(in, "an unknown method");
  if (plan.k < 1 || plan.k > 100000) throw bad(in, "k = " + std::to_string(plan.k) + " is out of range");
  if (!std::isfinite(plan.lattice.cell) || plan.lattice.cell <= 0.0 || !plan.offset.allFinite() ||
      !plan.lattice.origin.allFinite() || !std::isfinite(plan.halo) || !std::isfinite(plan.exact_margin))
    throw bad(in, "its lattice or its halo is not finite");
  for (const std::int32_t n : plan.lattice.size)
    if (n < 1 || n > Lattice<3>::max_cells_per_axis)
      throw bad(in, "its lattice has an axis of " + std::to_string(n) + " cubes");
  if (plan.tile_cubes < 1 || plan.ring < 0 || plan.walk_margin < plan.ring || plan.walk_margin > 1000)
    throw bad(in, "its tiles' size, ring or margin is out of range");
  std::set<std::uint32_t> ids;
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) {
    const TileInfo& info = plan.tiles[t];
    for (std::size_t a = 0; a < 3; ++a)
      if (info.index[a] < 0 || info.index[a] > (plan.lattice.size[a] - 1) / plan.tile_cubes)
        throw bad(in, at_record("tile", t) + "lies outside the grid of tiles");
    if (!ids.insert(info.id).second) throw bad(in, at_record("tile", t) + "its id is another tile's");
    if (info.core_points > info.points) throw bad(in, at_record("tile", t) + "more core points than points");
  }
}

}  // namespace

void write_plan(const TilePlan& plan, const std::filesystem::path& dir) {
  detail::BinaryWriter out(tile_files::plan(dir), plan_magic);
  out.put(static_cast<std::int32_t>(plan.method));
  out.put(plan.k);
  out.put(plan.spacing);
  out.put(static_cast<std::uint8_t>(plan.has_quadric_medians));
  out.put(plan.quadric_medians);
  put_optional(out, plan.rho);
  put_optional(out, plan.delta);
  out.put(plan.vote_rounds);
  out.put(plan.gap_factor);
  out.put(plan.min_component_points);
  put_vec(out, plan.offset);
  put_vec(out, plan.box.min);
  put_vec(out, plan.box.max);
  put_vec(out, plan.lattice.origin);
  out.put(plan.lattice.cell);
  out.put(plan.lattice.size);
  for (const double v : {plan.halo, plan.exact_margin, plan.radius_q, plan.rho_q, plan.seconds_statistics,
                         plan.seconds_binning, plan.seconds_bounds})
    out.put(v);
  out.put(plan.tile_cubes);
  out.put(plan.walk_margin);
  out.put(plan.ring);
  for (const double v : {plan.refinement.crease_angle_degrees, plan.refinement.chord_balance,
                         plan.refinement.fragment_fraction, plan.refinement.max_move})
    out.put(v);
  out.put(static_cast<std::uint8_t>(plan.refinement.keep_fragments));
  out.put(static_cast<std::uint8_t>(plan.refinement.keep_embedding));
  out.put(static_cast<std::uint8_t>(plan.colors));
  out.put(static_cast<std::uint8_t>(plan.normals));
  out.put(plan.color_blend.k);
  out.put(plan.input_points);
  out.put(plan.statistics_points);
  out.put_vector<TileInfo>(plan.tiles);
  out.commit();
}

TilePlan read_plan_file(const std::filesystem::path& path) {
  detail::BinaryReader in(path, plan_magic);
  TilePlan plan;
  plan.method = static_cast<Method>(in.get<std::int32_t>());
  plan.k = in.get<int>();
  plan.spacing = in.get<CloudSpacing>();
  plan.has_quadric_medians = in.get<std::uint8_t>() != 0;
  plan.quadric_medians = in.get<QuadricMedians>();
  plan.rho = get_optional<double>(in);
  plan.delta = get_optional<double>(in);
  plan.vote_rounds = in.get<int>();
  plan.gap_factor = in.get<double>();
  plan.min_component_points = in.get<int>();
  plan.offset = get_vec(in);
  plan.box.min = get_vec(in);
  plan.box.max = get_vec(in);
  plan.lattice.origin = get_vec(in);
  plan.lattice.cell = in.get<double>();
  plan.lattice.size = in.get<Lattice<3>::Index>();
  for (double* v : {&plan.halo, &plan.exact_margin, &plan.radius_q, &plan.rho_q, &plan.seconds_statistics,
                    &plan.seconds_binning, &plan.seconds_bounds})
    *v = in.get<double>();
  plan.tile_cubes = in.get<std::int32_t>();
  plan.walk_margin = in.get<std::int32_t>();
  plan.ring = in.get<std::int32_t>();
  for (double* v : {&plan.refinement.crease_angle_degrees, &plan.refinement.chord_balance,
                    &plan.refinement.fragment_fraction, &plan.refinement.max_move})
    *v = in.get<double>();
  plan.refinement.keep_fragments = in.get<std::uint8_t>() != 0;
  plan.refinement.keep_embedding = in.get<std::uint8_t>() != 0;
  plan.colors = in.get<std::uint8_t>() != 0;
  plan.normals = in.get<std::uint8_t>() != 0;
  plan.color_blend.k = in.get<int>();
  plan.input_points = in.get<std::uint64_t>();
  plan.statistics_points = in.get<std::uint64_t>();
  plan.tiles = in.get_vector<TileInfo>();
  in.finish();
  check_plan(in, plan);
  return plan;
}

void format_tile_name(char (&out)[tile_name_size], std::uint64_t id, const char* kind) noexcept {
  char digits[24];
  std::size_t count = 0;
  do {
    digits[count++] = static_cast<char>('0' + id % 10);
    id /= 10;
  } while (id > 0);
  while (count < 6) digits[count++] = '0';  // (at least six digits: tile-000042)
  std::size_t n = 0;
  for (const char c : {'t', 'i', 'l', 'e', '-'}) out[n++] = c;
  while (count > 0) out[n++] = digits[--count];
  out[n++] = '.';
  for (const char* c = kind; *c != '\0' && n + 1 < tile_name_size; ++c) out[n++] = *c;
  out[n] = '\0';
}

TilePoints read_points(const std::filesystem::path& dir, const TilePlan& plan, const TileInfo& info) {
  const std::vector<PointRecord> records = read_point_records(of_tile(dir, info.id, "points"));
  TilePoints t;
  t.positions.reserve(records.size());
  t.index.reserve(records.size());
  for (const PointRecord& r : records) {
    t.positions.emplace_back(r.x, r.y, r.z);
    t.index.push_back(r.index);
  }
  if (plan.colors) {
    const auto path = of_tile(dir, info.id, "colors");
    t.colors = read_colors(path);
    if (t.colors.size() != t.positions.size())
      throw ParseError(path.string() + ": " + std::to_string(t.colors.size()) + " colours for " +
                       std::to_string(t.positions.size()) + " points");
  }
  return t;
}

}  // namespace recon::tile_files

namespace recon {

TilePlan read_tile_plan(const std::filesystem::path& work_dir) {
  return tile_files::read_plan_file(tile_files::plan(work_dir));
}

}  // namespace recon
