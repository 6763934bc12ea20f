// A point-cloud PLY reader and writer just big enough for the peer benchmark
// (bench/peers.sh). The peers' own readers differ in what they accept (PCL's
// wants float, CGAL's wants its property maps), so both programs read and
// write through this one file and every program sees the same numbers.
//
// Reads: the `vertex` element of an ASCII or binary little-endian PLY, any
// scalar property types; keeps x y z and, when present, nx ny nz.
// Writes: binary little-endian PLY, double x y z nx ny nz, plus an optional
// uchar `oriented` per point (0 where a program left the normal unoriented).
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace peers {

struct PlyPoints {
  std::vector<std::array<double, 3>> positions;  // #P
  std::vector<std::array<double, 3>> normals;    // #P, or empty when the file has none
};

namespace detail {

inline std::size_t scalar_size(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32") return 4;
  if (type == "float" || type == "float32") return 4;
  if (type == "double" || type == "float64") return 8;
  throw std::runtime_error("PLY: unknown property type '" + type + "'");
}

inline double scalar_value(const std::string& type, const char* bytes) {
  auto as = [bytes](auto value) {
    std::memcpy(&value, bytes, sizeof value);
    return static_cast<double>(value);
  };
  if (type == "char" || type == "int8") return as(std::int8_t{});
  if (type == "uchar" || type == "uint8") return as(std::uint8_t{});
  if (type == "short" || type == "int16") return as(std::int16_t{});
  if (type == "ushort" || type == "uint16") return as(std::uint16_t{});
  if (type == "int" || type == "int32") return as(std::int32_t{});
  if (type == "uint" || type == "uint32") return as(std::uint32_t{});
  if (type == "float" || type == "float32") return as(float{});
  return as(double{});
}

}  // namespace detail

// Throws std::runtime_error on anything it does not understand.
inline PlyPoints read_ply_points(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::string line;
  std::getline(in, line);
  if (line.rfind("ply", 0) != 0) throw std::runtime_error(path + ": not a PLY file");

  struct Property {
    std::string type, name;
  };
  std::vector<Property> properties;
  std::string format, element;
  std::size_t count = 0;
  bool vertex_seen = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      words >> format;
    } else if (keyword == "element") {
      words >> element;
      if (element == "vertex") {
        words >> count;
        vertex_seen = true;
      } else if (!vertex_seen) {
        throw std::runtime_error(path + ": the vertex element must come first");
      }
    } else if (keyword == "property" && element == "vertex") {
      Property p;
      words >> p.type >> p.name;
      if (p.type == "list") throw std::runtime_error(path + ": list property in the vertex element");
      properties.push_back(p);
    } else if (keyword == "end_header") {
      break;
    }
  }
  if (!vertex_seen) throw std::runtime_error(path + ": no vertex element");
  if (format != "ascii" && format != "binary_little_endian")
    throw std::runtime_error(path + ": unsupported PLY format '" + format + "'");

  auto column = [&](const char* name) {
    for (std::size_t i = 0; i < properties.size(); ++i)
      if (properties[i].name == name) return static_cast<int>(i);
    return -1;
  };
  const std::array<int, 3> xyz{column("x"), column("y"), column("z")};
  const std::array<int, 3> nxyz{column("nx"), column("ny"), column("nz")};
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) throw std::runtime_error(path + ": no x y z");
  const bool has_normals = nxyz[0] >= 0 && nxyz[1] >= 0 && nxyz[2] >= 0;

  std::vector<std::size_t> offsets;
  std::size_t record = 0;
  for (const auto& p : properties) {
    offsets.push_back(record);
    record += detail::scalar_size(p.type);
  }

  PlyPoints cloud;
  cloud.positions.resize(count);
  if (has_normals) cloud.normals.resize(count);
  std::vector<double> values(properties.size());
  std::vector<char> bytes(record);
  for (std::size_t i = 0; i < count; ++i) {
    if (format == "ascii") {
      for (auto& v : values) in >> v;
    } else {
      in.read(bytes.data(), static_cast<std::streamsize>(record));
      for (std::size_t j = 0; j < properties.size(); ++j)
        values[j] = detail::scalar_value(properties[j].type, bytes.data() + offsets[j]);
    }
    if (!in) throw std::runtime_error(path + ": truncated at vertex " + std::to_string(i));
    for (int d = 0; d < 3; ++d) {
      cloud.positions[i][d] = values[xyz[d]];
      if (has_normals) cloud.normals[i][d] = values[nxyz[d]];
    }
  }
  return cloud;
}

// `oriented` is empty (no property written) or holds one flag per point.
inline void write_ply_points(const std::string& path, const PlyPoints& cloud,
                             const std::vector<std::uint8_t>& oriented = {}) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "ply\nformat binary_little_endian 1.0\ncomment written by bench/peers\n"
      << "element vertex " << cloud.positions.size() << "\n"
      << "property double x\nproperty double y\nproperty double z\n"
      << "property double nx\nproperty double ny\nproperty double nz\n";
  if (!oriented.empty()) out << "property uchar oriented\n";
  out << "end_header\n";
  for (std::size_t i = 0; i < cloud.positions.size(); ++i) {
    out.write(reinterpret_cast<const char*>(cloud.positions[i].data()), 3 * sizeof(double));
    out.write(reinterpret_cast<const char*>(cloud.normals[i].data()), 3 * sizeof(double));
    if (!oriented.empty()) out.write(reinterpret_cast<const char*>(&oriented[i]), 1);
  }
  if (!out) throw std::runtime_error("error while writing " + path);
}

}  // namespace peers
