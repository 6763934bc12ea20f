// SVG pictures of reconstructed curves: the samples, their oriented normals
// and the curves in one drawing that any browser shows.
//
// SVG's y axis points down, so every y is written negated: the picture has
// the data's orientation. The view box is the bounding box of everything
// drawn plus a margin; line widths and dot sizes are fractions of its
// diagonal, so the picture looks the same at any scale of the data. Each
// layer is a group with an id (points, normals, curves) for styling or
// hiding; each curve is one path, closed with 'Z' when the curve is closed.

#include "formats.h"
#include "io_detail.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace recon::io::detail {
namespace {

// SVG's y (0 - y rather than -y: no "-0" in the file).
double svg_y(double y) { return 0.0 - y; }

void append_point(std::string& out, const Vec2& p) {
  append_number(out, p.x());
  out += ',';
  append_number(out, svg_y(p.y()));
}

// The drawing's frame: the data's box with a margin for the normals, its
// size in pixels, and the width of a line.
struct Frame {
  Vec2 low, size;
  double width_px = 800.0, height_px = 0.0, line = 0.0, normal_length = 0.0;
};

Frame frame_of(const PolylineSet& curves, std::span<const Vec2> points, double normal_length) {
  Box<2> box;
  for (const Vec2& p : points) box.extend(p);
  for (const Vec2& v : curves.vertices) box.extend(v);
  if (box.empty()) box.extend(Vec2::Zero());
  const double diagonal = std::max(box.diagonal(), 1e-300);
  Frame f;
  f.normal_length = normal_length > 0.0 ? normal_length : diagonal / 40.0;
  const Vec2 margin = Vec2::Constant(0.04 * diagonal + f.normal_length);
  f.low = box.min - margin;
  f.size = box.extent() + 2.0 * margin;
  f.height_px = std::clamp(f.width_px * f.size.y() / f.size.x(), 100.0, 4000.0);
  f.line = diagonal / 600.0;
  return f;
}

void draw_header(std::string& out, const Frame& f, const PolylineSet& curves, std::size_t points) {
  out += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"";
  append_number(out, f.low.x());
  out += ' ';
  append_number(out, svg_y(f.low.y() + f.size.y()));
  out += ' ';
  append_number(out, f.size.x());
  out += ' ';
  append_number(out, f.size.y());
  out += "\" width=\"";
  append_number(out, f.width_px);
  out += "\" height=\"";
  append_number(out, std::round(f.height_px));
  out += "\">\n<title>recon: " + std::to_string(curves.polylines.size()) + " curves (" +
         std::to_string(curves.closed_count()) + " closed) from " + std::to_string(points) + " points</title>\n";
}

void draw_normals(BlockWriter& writer, const Frame& f, std::span<const Vec2> points, std::span<const Vec2> normals) {
  std::string& out = writer.buffer();
  out += "<g id=\"normals\" stroke=\"#3b82c4\" stroke-width=\"";
  append_number(out, f.line);
  out += "\" fill=\"none\">\n";
  for (std::size_t i = 0; i < normals.size() && i < points.size(); ++i) {
    out += "<path d=\"M";
    append_point(out, points[i]);
    out += " L";
    append_point(out, points[i] + f.normal_length * normals[i]);
    out += "\"/>\n";
    writer.flush_if_full();
  }
  out += "</g>\n";
}

void draw_points(BlockWriter& writer, const Frame& f, std::span<const Vec2> points) {
  std::string& out = writer.buffer();
  out += "<g id=\"points\" fill=\"#222\">\n";
  for (const Vec2& p : points) {
    out += "<circle cx=\"";
    append_number(out, p.x());
    out += "\" cy=\"";
    append_number(out, svg_y(p.y()));
    out += "\" r=\"";
    append_number(out, 2.0 * f.line);
    out += "\"/>\n";
    writer.flush_if_full();
  }
  out += "</g>\n";
}

void draw_curves(BlockWriter& writer, const Frame& f, const PolylineSet& curves) {
  std::string& out = writer.buffer();
  out += "<g id=\"curves\" stroke=\"#d22\" stroke-width=\"";
  append_number(out, 1.5 * f.line);
  out += "\" fill=\"none\" stroke-linejoin=\"round\">\n";
  for (const Polyline& curve : curves.polylines) {
    out += curve.closed ? "<path class=\"closed\" d=\"" : "<path class=\"open\" d=\"";
    for (std::size_t j = 0; j < curve.vertices.size(); ++j) {
      out += j == 0 ? "M" : " L";
      append_point(out, curves.vertices[curve.vertices[j]]);
      writer.flush_if_full();
    }
    if (curve.closed) out += " Z";
    out += "\"/>\n";
  }
  out += "</g>\n";
}

}  // namespace

void write_svg_curves(std::ostream& stream, const PolylineSet& curves, std::span<const Vec2> points,
                      std::span<const Vec2> normals, double normal_length) {
  const Frame frame = frame_of(curves, points, normal_length);
  BlockWriter writer(stream);
  draw_header(writer.buffer(), frame, curves, points.size());
  draw_normals(writer, frame, points, normals);
  draw_points(writer, frame, points);
  draw_curves(writer, frame, curves);
  writer.buffer() += "</svg>\n";
  writer.finish();
}

}  // namespace recon::io::detail
