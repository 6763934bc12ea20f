// Writes a report with a lab panel, made by hand (hand_made_lab.h), for the
// browser tests (web/tests/report.test.mjs): a sphere beside a torus, so
// that the complete graph's tree joins them and the Riemannian graph keeps
// them apart.
//   recon_report_lab_page OUT.html [POINTS]
// POINTS (4000 unless given) are sampled with a fixed seed.

#include "hand_made_lab.h"

#include "recon/core/shapes.h"
#include "recon/report/report.h"

#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::cerr << "usage: recon_report_lab_page OUT.html [POINTS]\n";
    return 2;
  }
  try {
    const std::size_t n = argc == 3 ? std::stoul(argv[2]) : 4000;
    const recon::PointCloud cloud = recon::make_sphere_and_torus()->sample(n, 7);
    const recon::testing::HandMadeLab lab = recon::testing::hand_made_lab(cloud);
    recon::ReportInput input;
    input.points = lab.points;
    input.planes = &lab.planes;
    input.oriented = &lab.default_orientation;
    input.normals = lab.default_orientation.normals;
    recon::ReportOptions options;
    options.title = "lab: sphere and torus";
    options.stats_json = lab.runs_json;
    recon::ReportLayers layers = recon::make_report_layers(input, options);
    layers.lab = recon::make_report_lab(lab.graphs, lab.runs_json, input.points, input.offset, layers, options);
    recon::write_report(argv[1], layers, options);
  } catch (const std::exception& e) {
    std::cerr << "recon_report_lab_page: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
