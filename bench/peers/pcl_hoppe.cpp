// PCL's answer to `recon reconstruct`: NormalEstimation (a plane per
// k-neighbourhood) and MarchingCubesHoppe (Hoppe's signed distance to the
// nearest point's tangent plane, contoured by marching cubes).
//
//   pcl_hoppe IN.ply -o MESH.ply [--normals-out NORMALS.ply] [--k K]
//             [--resolution R] [--extend F] [--threads T]
//             [--viewpoint X Y Z] [--dist-ignore L]
//
// K counts the point itself (PCL's k-NN search returns the query point), as
// recon's --k does. PCL has no orientation phase: every normal is flipped to
// face the viewpoint, the origin unless --viewpoint says otherwise. That is
// PCL's documented behaviour and what this program measures.
// R is the number of cubes along the longest side of the points' bounding
// box, as recon's --resolution: the cube side is that side / R. F widens the
// box by that fraction of its size (PCL's setPercentageExtendGrid; PCL never
// contours the outermost layer of cubes, so 0 would clip the surface), and
// each axis gets as many cubes as cover it at that side (PCL itself takes a
// count per axis and stretches the cubes to fit).
// L is the distance beyond which a lattice vertex is left undefined (PCL's
// setDistanceIgnore compares it with a squared distance, so L is squared
// here); without it every vertex gets a value, as in PCL's default.
// T: threads for the normals (1: NormalEstimation, otherwise
// NormalEstimationOMP with T threads, 0 meaning all cores). MarchingCubesHoppe
// is sequential.
// NORMALS.ply holds the input's points in the input's order with PCL's
// normals (double, as read). Prints one `step <name> <seconds> s` per step.
#include "ply_points.h"
#include "steps.h"

#include <pcl/PolygonMesh.h>
#include <pcl/common/common.h>
#include <pcl/common/io.h>
#include <pcl/features/normal_3d.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/marching_cubes_hoppe.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>

namespace {

struct Options {
  std::string input, output, normals_output;
  int k = 15;
  int resolution = 256;
  float extend = 0.05f;
  unsigned threads = 0;
  std::array<float, 3> viewpoint{0.0f, 0.0f, 0.0f};
  float dist_ignore = -1.0f;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "-o" || arg == "--output")
      o.output = value();
    else if (arg == "--normals-out")
      o.normals_output = value();
    else if (arg == "--k")
      o.k = std::stoi(value());
    else if (arg == "--resolution")
      o.resolution = std::stoi(value());
    else if (arg == "--extend")
      o.extend = std::stof(value());
    else if (arg == "--threads")
      o.threads = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--dist-ignore")
      o.dist_ignore = std::stof(value());
    else if (arg == "--viewpoint")
      for (auto& c : o.viewpoint) c = std::stof(value());
    else if (!arg.empty() && arg[0] != '-' && o.input.empty())
      o.input = arg;
    else
      throw std::runtime_error("unknown argument '" + arg + "'");
  }
  if (o.input.empty() || o.output.empty())
    throw std::runtime_error(
        "usage: pcl_hoppe IN.ply -o MESH.ply [--normals-out N.ply] [--k K] "
        "[--resolution R] [--extend F] [--threads T] [--viewpoint X Y Z] "
        "[--dist-ignore L]");
  if (o.k < 3) throw std::runtime_error("--k must be at least 3");
  if (o.resolution < 3) throw std::runtime_error("--resolution must be at least 3");
  return o;
}

template <typename Estimator>
void estimate(Estimator& estimator, const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, const Options& o,
              pcl::PointCloud<pcl::Normal>& normals) {
  estimator.setInputCloud(cloud);
  estimator.setSearchMethod(pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>));
  estimator.setKSearch(o.k);
  estimator.setViewPoint(o.viewpoint[0], o.viewpoint[1], o.viewpoint[2]);
  estimator.compute(normals);
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  const unsigned threads = o.threads == 0 ? std::max(1u, std::thread::hardware_concurrency()) : o.threads;
  std::printf("threads: %u for the normals (%s); marching cubes sequential\n", threads,
              threads == 1 ? "NormalEstimation" : "NormalEstimationOMP");
  std::printf("viewpoint: %g %g %g (PCL flips every normal to face it)\n", o.viewpoint[0], o.viewpoint[1],
              o.viewpoint[2]);
  peers::Steps steps;

  const peers::PlyPoints input = peers::read_ply_points(o.input);
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->reserve(input.positions.size());
  for (const auto& p : input.positions)
    cloud->push_back(pcl::PointXYZ(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])));
  steps.done("read");

  pcl::PointCloud<pcl::Normal> normals;
  if (threads == 1) {
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimator;
    estimate(estimator, cloud, o, normals);
  } else {
    pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> estimator(threads);
    estimate(estimator, cloud, o, normals);
  }
  steps.done("normals");

  const auto undefined_normals = static_cast<std::size_t>(
      std::count_if(normals.begin(), normals.end(), [](const pcl::Normal& n) { return !std::isfinite(n.normal_x); }));
  if (!o.normals_output.empty()) {
    peers::PlyPoints written;
    written.positions = input.positions;
    written.normals.resize(normals.size());
    for (std::size_t i = 0; i < normals.size(); ++i)
      written.normals[i] = {normals[i].normal_x, normals[i].normal_y, normals[i].normal_z};
    peers::write_ply_points(o.normals_output, written);
    steps.done("write_normals");
  }

  pcl::PointCloud<pcl::PointNormal>::Ptr oriented(new pcl::PointCloud<pcl::PointNormal>);
  pcl::concatenateFields(*cloud, normals, *oriented);
  pcl::PointXYZ lo, hi;
  pcl::getMinMax3D(*cloud, lo, hi);
  const std::array<float, 3> extent{hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
  const float cube = std::max({extent[0], extent[1], extent[2]}) / static_cast<float>(o.resolution);
  std::array<int, 3> cubes{};
  for (int d = 0; d < 3; ++d)
    cubes[d] = std::max(3, static_cast<int>(std::lround(extent[d] * (1.0f + o.extend) / cube)));

  pcl::MarchingCubesHoppe<pcl::PointNormal> contour;
  contour.setInputCloud(oriented);
  contour.setSearchMethod(pcl::search::KdTree<pcl::PointNormal>::Ptr(new pcl::search::KdTree<pcl::PointNormal>));
  contour.setGridResolution(cubes[0], cubes[1], cubes[2]);
  contour.setPercentageExtendGrid(o.extend);
  contour.setIsoLevel(0.0f);
  if (o.dist_ignore > 0) contour.setDistanceIgnore(o.dist_ignore * o.dist_ignore);
  pcl::PolygonMesh mesh;
  contour.reconstruct(mesh);
  steps.done("marching_cubes");

  pcl::io::savePLYFileBinary(o.output, mesh);
  steps.done("write_mesh");
  std::printf("lattice: %d x %d x %d (PCL's grid resolution), cube side %g\n", cubes[0], cubes[1], cubes[2],
              static_cast<double>(cube));
  std::printf("undefined normals: %zu of %zu points\n", undefined_normals, normals.size());
  std::printf("mesh: %u vertices (unwelded), %zu triangles\n", mesh.cloud.width * mesh.cloud.height,
              mesh.polygons.size());
  return 0;
} catch (const std::exception& e) {
  std::cerr << "pcl_hoppe: " << e.what() << "\n";
  return 1;
}
