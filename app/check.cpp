// recon check: is a mesh the boundary of a solid? The exact check of
// mesh_embedding.h on a mesh read from a file (recon's or another
// program's): the counts on one line, exit status 0 when the mesh is
// embedded and manifold, 1 (with a line naming the file) when it is not.

#include "commands.h"

#include "recon/core/errors.h"
#include "recon/io/mesh_io.h"
#include "recon/structures/mesh_embedding.h"

#include <iostream>
#include <memory>
#include <sstream>
#include <string>

namespace recon::cli {

namespace {

std::string counts(const MeshEmbedding& e) {
  std::ostringstream line;
  line << e.intersecting_pairs << " intersecting triangle pairs, " << e.non_manifold_vertices
       << " non-manifold (pinched) vertices, " << e.non_manifold_edges << " non-manifold edges, "
       << e.degenerate_triangles << " degenerate triangles";
  return line.str();
}

void run_check(const std::filesystem::path& input, const GlobalOptions& global) {
  const Mesh mesh = io::read_mesh(input);
  const MeshEmbedding e = check_embedding(mesh);
  if (!global.quiet)
    std::cout << "check     " << input.string() << ": " << mesh.vertices.size() << " vertices, "
              << mesh.triangles.size() << " triangles: " << counts(e) << (e.embedded() ? ": embedded" : "") << '\n';
  if (!e.embedded()) throw Error(input.string() + ": not embedded: " + counts(e));
}

}  // namespace

Command add_check(CLI::App& app, const GlobalOptions& global) {
  auto input = std::make_shared<std::filesystem::path>();
  app.add_option("mesh", *input, "Mesh to check (PLY, OBJ or OFF)")->required();
  return [input, &global] { run_check(*input, global); };
}

}  // namespace recon::cli
