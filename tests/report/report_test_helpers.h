// What both halves of the report's tests (report_test.cpp: the layers;
// report_page_test.cpp: the page, colours and the lab panel) build on: the
// reconstructions they draw, and reading a drawn position or a page element.

#pragma once

#include "recon/core/shapes.h"
#include "recon/reconstruct.h"

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace recon::report_testing {

inline Reconstruction reconstruct_for_report(const PointCloud& cloud) {
  ReconstructionOptions options;
  options.keep_graph = true;
  options.keep_corners = true;
  return reconstruct(cloud, options);
}

// A half sphere (open: the mesh has a boundary) beside a whole one, far
// enough apart to be two components.
inline const Reconstruction& open_and_closed() {
  static const Reconstruction r = [] {
    PointCloud cloud;
    for (const Vec3& p : make_sphere()->sample(6000, 5).positions)
      if (p.z() > 0.0) cloud.positions.push_back(p);
    for (const Vec3& p : make_sphere()->sample(3000, 6).positions) cloud.positions.push_back(p + Vec3(4.0, 0.0, 0.0));
    return reconstruct_for_report(cloud);
  }();
  return r;
}

inline Vec3 at(const std::vector<float>& v, std::size_t i) {
  return {static_cast<double>(v[3 * i]), static_cast<double>(v[3 * i + 1]), static_cast<double>(v[3 * i + 2])};
}

// The reconstructions of a small sphere by the refined method and by
// hoppe92 (layer 8 compares them).
inline const Reconstruction& small_sphere(Method method) {
  static const auto make = [](Method m) {
    ReconstructionOptions options;
    options.method = m;
    return reconstruct(make_sphere()->sample(2500, 21), options);
  };
  static const Reconstruction refined = make(Method::refined), hoppe92 = make(Method::hoppe92);
  return method == Method::refined ? refined : hoppe92;
}

// The text of the element with this id.
inline std::string_view element(std::string_view html, const std::string& id) {
  const std::string open = "id=\"" + id + "\"";
  const auto at = html.find(open);
  if (at == std::string_view::npos) return {};
  const auto start = html.find('>', at) + 1;
  return html.substr(start, html.find("</script>", start) - start);
}

}  // namespace recon::report_testing
