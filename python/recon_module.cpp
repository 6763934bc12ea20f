// recon._recon: the compiled part of the Python package (python/recon/
// __init__.py wraps it). It hands numpy arrays to the library as they are
// and hands the library's results back as numpy arrays over recon's own
// buffers:
//
//   points in:  a C-contiguous float64 n x 3 array is seen in place as
//               std::span<const Vec3> (PointCloudView); other arrays of
//               real numbers (float32, integers, strided) are converted
//               once by numpy. An array of another kind (complex, bool,
//               strings, objects; float face indices) is a TypeError
//               naming the argument: numpy's cast would drop an imaginary
//               part or truncate an index 1.7 to 1 without a word.
//   arrays out: views of the vectors inside a Mesh or PointCloud object,
//               which each array keeps alive (its `base`): no copy.
//   while recon works the GIL is released; at each phase the run takes it
//   back for a moment to call the progress callback, and between the
//   phases' steps to check for signals (interruption.h: Ctrl-C raises
//   KeyboardInterrupt out of the run).
//   errors:     InvalidInputError, ParseError -> ValueError;
//               ResourceLimitError -> recon.ResourceLimitError (a MemoryError);
//               IoError -> FileNotFoundError, IsADirectoryError,
//               PermissionError or OSError; the message is the program's.
//   tiles:      the steps of a tiled run (tiles.h), one call each
//               (_tiles_*), for recon.distributed (recon/distributed.py),
//               which runs steps 2 and 4 as Dask tasks; each returns its
//               figures as a dict.
// Statistics are made by the program's own code (app/run_reports.h), so a
// mesh's `stats` holds what `recon reconstruct --stats` writes.

#include "run_reports.h"
#include "summary.h"

#include "recon/core/errors.h"
#include "recon/core/interruption.h"
#include "recon/core/parallel.h"
#include "recon/core/timer.h"
#include "recon/core/version.h"
#include "recon/estimate_normals.h"
#include "recon/io/atomic_file.h"
#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"
#include "recon/reconstruct.h"
#include "recon/tiles/tiles.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace py = pybind11;
using namespace pybind11::literals;  // "name"_a = value

namespace recon::python {
namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "a Vec3 is three packed doubles");
static_assert(sizeof(Color) == 3, "a Color is three packed bytes");

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using ByteArray = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>;

// ---------------------------------------------------------------------------
// Arrays in

std::string shape_of(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d > 0 ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

// `value` as a numpy array (a list becomes one, as numpy.asarray makes it).
py::array array_of(py::handle value, const char* name) {
  py::array a = py::array::ensure(value);
  if (!a)
    throw py::type_error(std::string(name) + " must be an array, got " +
                         py::str(py::type::of(value)).cast<std::string>());
  return a;
}

std::string dtype_of(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

// `a` converted by numpy to `Array`'s dtype and layout (no copy when it has them).
template <class Array>
Array converted(const py::array& a, const char* name) {
  Array result = Array::ensure(a);
  if (!result) throw py::type_error(std::string(name) + ": numpy cannot convert dtype " + dtype_of(a));
  return result;
}

// `value` as float64, refusing what numpy would cast with a loss or a guess.
// Throws TypeError unless its dtype is a real number (float, int, uint).
DoubleArray real_array(py::handle value, const char* name) {
  const py::array a = array_of(value, name);
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + " must hold real numbers; got dtype " + dtype_of(a));
  return converted<DoubleArray>(a, name);
}

std::optional<DoubleArray> real_array_or_none(py::handle value, const char* name) {
  if (value.is_none()) return std::nullopt;
  return real_array(value, name);
}

using IndexArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// `value` as int64 vertex indices. Throws TypeError unless its dtype is an
// integer: a float index (1.7) is not a vertex, whatever numpy would make of it.
IndexArray index_array(py::handle value, const char* name) {
  const py::array a = array_of(value, name);
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + " must hold integer vertex indices; got dtype " + dtype_of(a));
  return converted<IndexArray>(a, name);
}

// Colours as given to the compiled module: uint8 only (the package turns
// floats in [0, 1] and other integers into uint8 after checking their range).
std::optional<ByteArray> byte_array_or_none(py::handle value, const char* name) {
  if (value.is_none()) return std::nullopt;
  const py::array a = array_of(value, name);
  if (a.dtype().kind() != 'u' || a.dtype().itemsize() != 1)
    throw py::type_error(std::string(name) + " must be uint8 values 0-255; got dtype " + dtype_of(a));
  return converted<ByteArray>(a, name);
}

// Checks that `a` is n x 3 (n = `rows` when given) and returns n.
std::size_t rows_of(const py::array& a, const char* name, std::optional<std::size_t> rows) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw InvalidInputError(std::string(name) + " must be an n x 3 array; got shape " + shape_of(a));
  const auto n = static_cast<std::size_t>(a.shape(0));
  if (rows && n != *rows)
    throw InvalidInputError(std::string(name) + " must have one row per point: " + std::to_string(*rows) + " points, " +
                            std::to_string(n) + " rows");
  return n;
}

template <typename T, typename Array>
bool aligned_for(const Array& a) {
  return reinterpret_cast<std::uintptr_t>(a.data()) % alignof(T) == 0;
}

// The arrays of a cloud given from Python, seen in place. A float64 array
// that numpy placed at an address no double may start at (a view into
// bytes) is copied once instead.
struct CloudArrays {
  DoubleArray points, normals;
  ByteArray colors;
  PointCloud copies;  // only for misaligned input
  PointCloudView view;

  // Throws TypeError for an array of the wrong kind, ValueError for a wrong shape.
  CloudArrays(py::handle p, py::handle n, py::handle c) : points(real_array(p, "points")) {
    view_arrays(real_array_or_none(n, "normals"), byte_array_or_none(c, "colors"));
  }

 private:
  void view_arrays(std::optional<DoubleArray> n, std::optional<ByteArray> c) {
    const std::size_t count = rows_of(points, "points", std::nullopt);
    view.positions = vectors_of(points, count, copies.positions);
    if (n) {
      normals = std::move(*n);
      rows_of(normals, "normals", count);
      view.normals = vectors_of(normals, count, copies.normals);
    }
    if (c) {
      colors = std::move(*c);
      rows_of(colors, "colors", count);
      view.colors = {reinterpret_cast<const Color*>(colors.data()), count};
    }
  }

  static std::span<const Vec3> vectors_of(const DoubleArray& a, std::size_t count, std::vector<Vec3>& copy) {
    if (count == 0) return {};
    if (aligned_for<Vec3>(a)) return {reinterpret_cast<const Vec3*>(a.data()), count};
    copy.resize(count);
    std::memcpy(static_cast<void*>(copy.data()), a.data(), count * sizeof(Vec3));
    return copy;
  }
};

// A PointCloud holding copies of the view's arrays (for the objects made
// from arrays, and the writers, which take a PointCloud).
PointCloud copy_of(const PointCloudView& view) {
  PointCloud cloud;
  cloud.positions.assign(view.positions.begin(), view.positions.end());
  cloud.normals.assign(view.normals.begin(), view.normals.end());
  cloud.colors.assign(view.colors.begin(), view.colors.end());
  return cloud;
}

// ---------------------------------------------------------------------------
// Arrays out: views of a vector inside `owner` (a Python object that keeps it alive)

py::array vectors_view(const std::vector<Vec3>& values, py::handle owner) {
  return py::array_t<double>({static_cast<py::ssize_t>(values.size()), py::ssize_t{3}},
                             {static_cast<py::ssize_t>(sizeof(Vec3)), static_cast<py::ssize_t>(sizeof(double))},
                             reinterpret_cast<const double*>(values.data()), owner);
}

py::array colors_view(const std::vector<Color>& values, py::handle owner) {
  return py::array_t<std::uint8_t>({static_cast<py::ssize_t>(values.size()), py::ssize_t{3}},
                                   {py::ssize_t{3}, py::ssize_t{1}},
                                   reinterpret_cast<const std::uint8_t*>(values.data()), owner);
}

py::array faces_view(const std::vector<std::array<std::uint32_t, 3>>& faces, py::handle owner) {
  // Vertex indices are below 2^31 (checked when the mesh is made), so the
  // unsigned indices read the same as int32.
  return py::array_t<std::int32_t>({static_cast<py::ssize_t>(faces.size()), py::ssize_t{3}},
                                   {py::ssize_t{12}, py::ssize_t{4}},
                                   reinterpret_cast<const std::int32_t*>(faces.data()), owner);
}

// ---------------------------------------------------------------------------
// The objects Python holds

struct PyPointCloud {
  PointCloud cloud;
  std::vector<std::string> notes;  // what the reader chose or skipped
};

struct PyMesh {
  Mesh mesh;
  py::dict stats;
};

Mesh mesh_from_arrays(const DoubleArray& vertices, const IndexArray& faces, const std::optional<ByteArray>& colors,
                      const std::optional<DoubleArray>& normals) {
  Mesh mesh;
  const std::size_t n = rows_of(vertices, "vertices", std::nullopt);
  const auto* v = vertices.data();
  mesh.vertices.resize(n);
  for (std::size_t i = 0; i < n; ++i) mesh.vertices[i] = Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  const std::size_t f = rows_of(faces, "faces", std::nullopt);
  const auto* t = faces.data();
  mesh.triangles.resize(f);
  for (std::size_t i = 0; i < 3 * f; ++i) {
    if (t[i] < 0 || static_cast<std::uint64_t>(t[i]) >= n)
      throw InvalidInputError("faces: index " + std::to_string(t[i]) + " in face " + std::to_string(i / 3) +
                              " is not a vertex (there are " + std::to_string(n) + ")");
    mesh.triangles[i / 3][i % 3] = static_cast<std::uint32_t>(t[i]);
  }
  if (colors) {
    rows_of(*colors, "colors", n);
    mesh.colors.resize(n);
    std::memcpy(static_cast<void*>(mesh.colors.data()), colors->data(), 3 * n);
  }
  if (normals) {  // (unit or not: write_mesh refuses what is not)
    rows_of(*normals, "normals", n);
    const auto* a = normals->data();
    mesh.normals.resize(n);
    for (std::size_t i = 0; i < n; ++i) mesh.normals[i] = Vec3(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
  }
  return mesh;
}

// ---------------------------------------------------------------------------
// Running: threads, the GIL, progress and Ctrl-C

// Sets the thread count for one call and puts the previous one back.
class ThreadsForOneCall {
 public:
  explicit ThreadsForOneCall(std::optional<int> threads) : previous_(thread_count()) {
    if (!threads) return;
    if (*threads < 1) throw InvalidInputError("threads must be at least 1, got " + std::to_string(*threads));
    set_thread_count(*threads);
  }
  ~ThreadsForOneCall() { set_thread_count(previous_); }
  ThreadsForOneCall(const ThreadsForOneCall&) = delete;
  ThreadsForOneCall& operator=(const ThreadsForOneCall&) = delete;

 private:
  int previous_;
};

// Raises a pending KeyboardInterrupt (Ctrl-C) out of the run: installed on
// the calling thread as the library's interruption check (interruption.h),
// which the phases run between their steps, without the GIL.
void check_signals() {
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

// What a run does as each phase starts (called on the calling thread,
// without the GIL): note the step for the memory peaks, then, holding the
// GIL, raise a pending KeyboardInterrupt and call the progress callback.
// `progress` is borrowed (the caller's reference keeps it alive): a handle,
// so that copying the hook without the GIL touches no reference count.
std::function<void(const char*)> phase_hook(StepPeaks& memory, py::handle progress) {
  return [&memory, progress](const char* phase) {
    memory.start(phase);
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!progress.is_none()) progress(phase);
  };
}

py::dict dict_of(const cli::Json& json) {
  return py::module_::import("json").attr("loads")(json.dump(0)).cast<py::dict>();
}

void check_range(std::optional<double> value, const char* name, bool zero_allowed) {
  if (!value) return;
  if (zero_allowed ? !(*value >= 0.0) : !(*value > 0.0))
    throw InvalidInputError(std::string(name) + " must be " + (zero_allowed ? "zero or more" : "positive") + ", got " +
                            std::to_string(*value));
}

// The options `recon reconstruct` and `recon normals` share, checked as the
// program checks them. Counts are taken as int64, so that a count beyond
// int (k = 10**11) gets the range's message, not pybind11's list of overloads.
struct PhaseParameters {
  std::optional<std::int64_t> k;
  std::optional<double> rho;
  std::size_t max_memory = 0;

  [[nodiscard]] TangentPlaneOptions planes() const {
    TangentPlaneOptions options;
    if (k) {
      if (*k < 3 || *k > 256) throw InvalidInputError("k must be between 3 and 256, got " + std::to_string(*k));
      options.k = static_cast<int>(*k);
      options.adapt_k = false;
    }
    check_range(rho, "rho", false);
    options.rho = rho;
    return options;
  }
};

std::size_t memory_limit(const py::object& max_memory) {
  if (max_memory.is_none()) return 0;
  std::size_t bytes = 0;
  const auto text = py::str(max_memory).cast<std::string>();  // "8G", or a count of bytes
  const std::string error = cli::parse_size(text, bytes);
  if (!error.empty()) throw InvalidInputError("max_memory: " + error);
  return bytes;
}

struct ReconstructParameters {
  PhaseParameters phases;
  std::optional<double> delta, cell;
  std::optional<std::int64_t> resolution;
  std::string method = "refined";
  bool keep_fragments = false;
  bool vertex_normals = false;  // the mesh's vertex normals (ReconstructionOptions::vertex_normals)
  std::optional<int> threads;
  std::optional<std::filesystem::path> report;
  py::object progress = py::none();
  SimplifyStep simplify{};

  [[nodiscard]] ReconstructionOptions options(bool use_normals) const {
    ReconstructionOptions o;
    o.method = method_from_name(method);
    o.planes = phases.planes();
    check_range(delta, "delta", true);
    check_range(cell, "cell", false);
    if (resolution && (*resolution < 1 || *resolution > (1 << 20)))
      throw InvalidInputError("resolution must be between 1 and 1048576, got " + std::to_string(*resolution));
    if (cell && resolution) throw InvalidInputError("give cell or resolution, not both");
    o.distance.delta = delta;
    o.cell = cell;
    if (resolution) o.resolution = static_cast<int>(*resolution);
    o.refinement.keep_fragments = keep_fragments;
    o.vertex_normals = vertex_normals;
    o.use_input_normals = use_normals;
    o.max_memory = phases.max_memory;
    o.keep_graph = report.has_value();
    o.keep_corners = report.has_value();
    o.simplify = simplify;
    return o;
  }
};

// simplify= and max_error=: an int is a triangle count, a float below 1 a
// ratio (the program's --simplify also takes "10%").
SimplifyStep simplify_step(const py::object& target, std::optional<double> max_error) {
  SimplifyStep step;
  const std::string expected =
      "simplify: expected a triangle count (an int of 1 or more) or a ratio (a float between 0 and 1)";
  if (py::isinstance<py::bool_>(target)) throw InvalidInputError(expected + ", got a bool");
  if (py::isinstance<py::int_>(target)) {
    const auto n = target.cast<long long>();
    if (n < 1) throw InvalidInputError(expected + ", got " + std::to_string(n));
    step.triangles = static_cast<std::size_t>(n);
  } else if (py::isinstance<py::float_>(target)) {
    const auto r = target.cast<double>();
    if (!(r > 0.0 && r < 1.0)) throw InvalidInputError(expected + ", got " + std::to_string(r));
    step.ratio = r;
  } else if (!target.is_none()) {
    throw InvalidInputError(expected);
  }
  if (max_error) {
    if (!(*max_error > 0.0) || !std::isfinite(*max_error))
      throw InvalidInputError("max_error: expected a finite multiple of rho greater than 0, got " +
                              std::to_string(*max_error));
    step.max_error = *max_error;
  }
  return step;
}

// The parameters reconstruct() and the tiled plan share.
ReconstructParameters reconstruct_parameters(std::optional<std::int64_t> k, std::optional<double> rho,
                                             std::optional<double> delta, std::optional<double> cell,
                                             std::optional<std::int64_t> resolution, const std::string& method,
                                             const py::object& max_memory) {
  ReconstructParameters p;
  p.phases = PhaseParameters{k, rho, memory_limit(max_memory)};
  p.delta = delta;
  p.cell = cell;
  p.resolution = resolution;
  p.method = method;
  return p;
}

std::unique_ptr<PyMesh> run_reconstruct(const CloudArrays& input, const ReconstructParameters& p) {
  const ReconstructionOptions checked = p.options(input.view.has_normals());
  ThreadsForOneCall threads(p.threads);
  auto result = std::make_unique<PyMesh>();
  cli::Summary summary(true);
  {
    py::gil_scoped_release no_gil;
    Timer total;
    InterruptionCheck interruptible(check_signals);
    StepPeaks memory;
    ReconstructionOptions options = checked;
    options.on_phase = phase_hook(memory, p.progress);
    Reconstruction r = reconstruct(input.view, options);
    memory.start("summary");
    cli::Json& in = summary.stats()["input"];
    in["points"] = input.view.size();
    in["has_normals"] = input.view.has_normals();
    in["has_colors"] = input.view.has_colors();
    cli::report_reconstruction(r, options, input.view.size(), p.report.has_value(), summary);
    cli::report_memory(memory, summary);
    summary.stats()["threads"] = thread_count();
    summary.stats()["seconds_total"] = total.elapsed();
    if (p.report) cli::write_run_report(*p.report, report_input(r), "recon.reconstruct", summary);
    if (r.simplification) {
      result->mesh = std::move(r.simplification->mesh);
    } else if (r.refinement) {
      result->mesh = std::move(r.refinement->mesh);
    } else {
      result->mesh = std::move(r.contour.mesh);
    }
  }
  if (result->mesh.vertices.size() >= (std::size_t{1} << 31))
    throw ResourceLimitError("the mesh has more than 2^31 vertices, more than int32 faces can index");
  result->stats = dict_of(summary.stats());
  return result;
}

py::tuple run_estimate_normals(const CloudArrays& input, const PhaseParameters& p, const std::string& method,
                               std::optional<int> threads_wanted, const py::object& progress) {
  NormalEstimationOptions options;
  options.method = method_from_name(method);  // (ValueError for another name, before any work)
  options.planes = p.planes();
  options.max_memory = p.max_memory;
  ThreadsForOneCall threads(threads_wanted);
  auto normals = std::make_unique<std::vector<Vec3>>();
  cli::Summary summary(true);
  {
    py::gil_scoped_release no_gil;
    InterruptionCheck interruptible(check_signals);
    StepPeaks memory;
    options.on_phase = phase_hook(memory, progress);
    const NormalEstimation estimated = estimate_normals(input.view, options);
    summary.stats()["input"]["points"] = input.view.size();
    cli::report_normal_estimation(estimated, input.view.size(), summary);
    cli::report_memory(memory, summary);
    summary.stats()["threads"] = thread_count();
    *normals = estimated.normals_in_input_order();
  }
  // The array owns the vector through a capsule: no copy.
  auto* held = normals.release();
  py::capsule owner(held, [](void* v) { delete static_cast<std::vector<Vec3>*>(v); });
  return py::make_tuple(vectors_view(*held, owner), dict_of(summary.stats()));
}

// The reader's options as read_points() and the tiled plan take them.
io::ReadPointsOptions read_options(const std::optional<std::string>& format,
                                   const std::optional<std::vector<std::string>>& columns, bool skip_invalid) {
  io::ReadPointsOptions options;
  if (format) options.format = io::point_format_from_name(*format);
  if (columns) options.columns = *columns;
  options.skip_invalid = skip_invalid;
  return options;
}

// ---------------------------------------------------------------------------
// Tiled runs (tiles.h), one step per call, for recon.distributed: it runs
// steps 1, 3 and 5 itself and steps 2 and 4 as Dask tasks on the workers.
// Each step releases the GIL while it works and stops on Ctrl-C (on the
// main thread); its figures come back as a dict.

// Runs `step()` without the GIL, interruptible, on `threads` threads (all
// when not given).
template <class Step>
auto run_tile_step(std::optional<int> threads, const Step& step) {
  ThreadsForOneCall use(threads);
  py::gil_scoped_release no_gil;
  InterruptionCheck interruptible(check_signals);
  return step();
}

py::dict plan_summary(const TilePlan& plan) {
  py::list points, core_points;
  for (const TileInfo& tile : plan.tiles) {
    points.append(tile.points);
    core_points.append(tile.core_points);
  }
  return py::dict("tiles"_a = plan.tiles.size(), "input_points"_a = plan.input_points,
                  "statistics_points"_a = plan.statistics_points,
                  "statistics_over_tiles"_a = plan.statistics_over_tiles, "method"_a = method_name(plan.method),
                  "k"_a = plan.k, "cell"_a = plan.lattice.cell, "tile_size"_a = plan.tile_cubes * plan.lattice.cell,
                  "halo"_a = plan.halo, "tile_points"_a = points, "tile_core_points"_a = core_points,
                  "seconds"_a = plan.seconds_bounds + plan.seconds_statistics + plan.seconds_binning);
}

py::dict orientation_summary(const TileOrientation& o) {
  return py::dict("points"_a = o.points, "pieces"_a = o.pieces, "border_samples"_a = o.border_samples,
                  "inexact_samples"_a = o.inexact_samples, "seconds"_a = o.seconds);
}

py::dict reconciliation_summary(const TileReconciliation& r) {
  return py::dict("nodes"_a = r.nodes, "edges"_a = r.edges, "objects"_a = r.objects, "turned"_a = r.turned,
                  "shared_samples"_a = r.shared_samples, "disagreeing"_a = r.disagreeing, "seconds"_a = r.seconds);
}

py::dict contour_summary(const TileContour& c) {
  return py::dict("vertices"_a = c.vertices, "triangles"_a = c.triangles, "visited_cubes"_a = c.visited_cubes,
                  "seconds"_a = c.seconds);
}

py::dict mesh_summary(const StitchedMesh& m) {
  return py::dict("vertices"_a = m.vertices, "triangles"_a = m.triangles, "welded"_a = m.welded,
                  "crease_vertices"_a = m.crease_vertices, "trimmed_triangles"_a = m.trimmed,
                  "stray_triangles"_a = m.stray_triangles, "fragments"_a = m.fragments,
                  "fragment_triangles"_a = m.fragment_triangles, "seconds"_a = m.seconds);
}

// ---------------------------------------------------------------------------
// Exceptions

void translate(std::exception_ptr failure) {
  try {
    if (failure) std::rethrow_exception(failure);
  } catch (const IoError& e) {
    PyObject* type = PyExc_OSError;
    if (e.error_code() == ENOENT) type = PyExc_FileNotFoundError;
    if (e.error_code() == EISDIR) type = PyExc_IsADirectoryError;
    if (e.error_code() == EACCES || e.error_code() == EPERM) type = PyExc_PermissionError;
    PyErr_SetString(type, e.what());
  } catch (const InvalidInputError& e) {
    PyErr_SetString(PyExc_ValueError, e.what());
  } catch (const ParseError& e) {
    PyErr_SetString(PyExc_ValueError, e.what());
  }
}

// ---------------------------------------------------------------------------
// The module's parts

void bind_point_cloud(py::module_& m) {
  py::class_<PyPointCloud>(m, "PointCloud")
      .def(py::init([](const py::object& points, const py::object& normals, const py::object& colors) {
             const CloudArrays in(points, normals, colors);
             auto result = std::make_unique<PyPointCloud>();
             result->cloud = copy_of(in.view);
             return result;
           }),
           py::arg("points"), py::arg("normals") = py::none(), py::arg("colors") = py::none())
      .def_property_readonly(
          "points", [](py::object self) { return vectors_view(self.cast<PyPointCloud&>().cloud.positions, self); })
      .def_property_readonly("normals",
                             [](py::object self) -> py::object {
                               const PointCloud& c = self.cast<PyPointCloud&>().cloud;
                               return c.has_normals() ? py::object(vectors_view(c.normals, self)) : py::none();
                             })
      .def_property_readonly("colors",
                             [](py::object self) -> py::object {
                               const PointCloud& c = self.cast<PyPointCloud&>().cloud;
                               return c.has_colors() ? py::object(colors_view(c.colors, self)) : py::none();
                             })
      .def_readonly("notes", &PyPointCloud::notes)
      .def("__len__", [](const PyPointCloud& c) { return c.cloud.size(); });
}

void bind_mesh(py::module_& m) {
  py::class_<PyMesh>(m, "Mesh")
      .def(py::init([](const py::object& vertices, const py::object& faces, const py::object& colors,
                       const py::object& normals) {
             auto result = std::make_unique<PyMesh>();
             result->mesh =
                 mesh_from_arrays(real_array(vertices, "vertices"), index_array(faces, "faces"),
                                  byte_array_or_none(colors, "colors"), real_array_or_none(normals, "normals"));
             return result;
           }),
           py::arg("vertices"), py::arg("faces"), py::arg("colors") = py::none(), py::arg("normals") = py::none())
      .def_property_readonly("vertices",
                             [](py::object self) { return vectors_view(self.cast<PyMesh&>().mesh.vertices, self); })
      .def_property_readonly("faces",
                             [](py::object self) { return faces_view(self.cast<PyMesh&>().mesh.triangles, self); })
      .def_property_readonly("colors",
                             [](py::object self) -> py::object {
                               const Mesh& mesh = self.cast<PyMesh&>().mesh;
                               return mesh.has_colors() ? py::object(colors_view(mesh.colors, self)) : py::none();
                             })
      .def_property_readonly("normals",
                             [](py::object self) -> py::object {
                               const Mesh& mesh = self.cast<PyMesh&>().mesh;
                               return mesh.has_normals() ? py::object(vectors_view(mesh.normals, self)) : py::none();
                             })
      .def_readonly("stats", &PyMesh::stats)
      .def(
          "save",
          [](const PyMesh& self, const std::filesystem::path& path, bool ascii) {
            io::WriteMeshOptions options;
            options.format = io::mesh_format_from_path(path);
            options.ascii = ascii;
            py::gil_scoped_release no_gil;
            io::write_mesh(path, self.mesh, options);
          },
          py::arg("path"), py::arg("ascii") = false);
}

void bind_files(py::module_& m) {
  m.def(
      "read_points",
      [](const std::filesystem::path& path, const std::optional<std::string>& format,
         const std::optional<std::vector<std::string>>& columns, bool skip_invalid) {
        const io::ReadPointsOptions options = read_options(format, columns, skip_invalid);
        auto result = std::make_unique<PyPointCloud>();
        io::ReadNotes notes;
        {
          py::gil_scoped_release no_gil;
          result->cloud = io::read_points(path, options, &notes);
        }
        result->notes = std::move(notes.lines);
        return result;
      },
      py::arg("path"), py::arg("format") = py::none(), py::arg("columns") = py::none(),
      py::arg("skip_invalid") = false);

  m.def(
      "write_points",
      [](const std::filesystem::path& path, const py::object& points, const py::object& normals,
         const py::object& colors, bool ascii) {
        const CloudArrays in(points, normals, colors);
        const PointCloud cloud = copy_of(in.view);  // the writers take a PointCloud: one copy, for the file
        io::WritePointsOptions options;
        options.ascii = ascii;
        py::gil_scoped_release no_gil;
        io::write_points(path, cloud, options);
      },
      py::arg("path"), py::arg("points"), py::arg("normals") = py::none(), py::arg("colors") = py::none(),
      py::arg("ascii") = false);

  // `text` into the file `path` the way the program writes every output
  // (io::AtomicFile): whole or not at all, never half a file. For
  // recon.distributed's --stats. Throws OSError when it cannot.
  m.def(
      "_write_text",
      [](const std::filesystem::path& path, const std::string& text) {
        py::gil_scoped_release no_gil;
        io::AtomicFile file(path);
        file.stream() << text;
        file.commit();
      },
      py::arg("path"), py::arg("text"));
}

void bind_runs(py::module_& m) {
  m.def(
      "estimate_normals",
      [](const py::object& points, std::optional<std::int64_t> k, std::optional<double> rho, std::optional<int> threads,
         const py::object& max_memory, const py::object& progress, const std::string& method) {
        const CloudArrays in(points, py::none(), py::none());
        PhaseParameters p{k, rho, memory_limit(max_memory)};
        return run_estimate_normals(in, p, method, threads, progress);
      },
      py::arg("points"), py::arg("k") = py::none(), py::arg("rho") = py::none(), py::arg("threads") = py::none(),
      py::arg("max_memory") = py::none(), py::arg("progress") = py::none(), py::arg("method") = "refined");

  m.def(
      "reconstruct",
      [](const py::object& points, const py::object& normals, const py::object& colors, std::optional<std::int64_t> k,
         std::optional<double> rho, std::optional<double> delta, std::optional<double> cell,
         std::optional<std::int64_t> resolution, const std::string& method, bool keep_fragments,
         const py::object& max_memory, std::optional<int> threads, std::optional<std::filesystem::path> report,
         const py::object& progress, bool vertex_normals, const py::object& simplify, std::optional<double> max_error) {
        const CloudArrays in(points, normals, colors);
        ReconstructParameters p = reconstruct_parameters(k, rho, delta, cell, resolution, method, max_memory);
        p.simplify = simplify_step(simplify, max_error);
        p.keep_fragments = keep_fragments;
        p.vertex_normals = vertex_normals;
        p.threads = threads;
        p.report = std::move(report);
        p.progress = progress;
        return run_reconstruct(in, p);
      },
      py::arg("points"), py::arg("normals") = py::none(), py::arg("colors") = py::none(), py::arg("k") = py::none(),
      py::arg("rho") = py::none(), py::arg("delta") = py::none(), py::arg("cell") = py::none(),
      py::arg("resolution") = py::none(), py::arg("method") = "refined", py::arg("keep_fragments") = false,
      py::arg("max_memory") = py::none(), py::arg("threads") = py::none(), py::arg("report") = py::none(),
      py::arg("progress") = py::none(), py::arg("vertex_normals") = false, py::arg("simplify") = py::none(),
      py::arg("max_error") = py::none());

  // For the tests: the address of the data the library would read for
  // `points` (equal to the array's own when no copy was made).
  m.def("_input_address", [](const py::object& points) {
    const CloudArrays in(points, py::none(), py::none());
    return reinterpret_cast<std::uintptr_t>(in.view.positions.data());
  });
}

// A folder for recon.distributed's files, as the program makes its own
// (TileWorkspace): made exclusively, locked for its life, the stale ones in
// `parent` removed first; close() or the end of a with block removes it.
struct PythonWorkspace {
  std::optional<TileWorkspace> workspace;
};

void bind_tile_workspace(py::module_& m) {
  py::class_<PythonWorkspace>(m, "_TileWorkspace")
      .def(py::init([](const std::filesystem::path& parent) {
             auto p = std::make_unique<PythonWorkspace>();
             p->workspace.emplace(parent);
             return p;
           }),
           py::arg("parent"))
      .def_property_readonly("path",
                             [](const PythonWorkspace& p) {
                               if (!p.workspace) throw py::value_error("the tiles' workspace is closed");
                               return p.workspace->path();
                             })
      .def("close", [](PythonWorkspace& p) { p.workspace.reset(); })
      .def(
          "__enter__", [](PythonWorkspace& p) -> PythonWorkspace& { return p; }, py::return_value_policy::reference)
      .def("__exit__", [](PythonWorkspace& p, const py::args&) { p.workspace.reset(); });
  m.def("_tiles_remove_stale_workspaces", &remove_stale_tile_workspaces, py::arg("parent"));
}

void bind_tiles(py::module_& m) {
  m.def(
      "_tiles_plan",
      [](const std::filesystem::path& input, const std::filesystem::path& work_dir, const std::string& method,
         std::optional<std::int64_t> k, std::optional<double> rho, std::optional<double> delta,
         std::optional<double> cell, std::optional<std::int64_t> resolution, double tile_size,
         const py::object& max_memory, std::size_t statistics_points, const std::optional<std::string>& format,
         const std::optional<std::vector<std::string>>& columns, bool skip_invalid, bool vertex_normals) {
        ReconstructParameters p = reconstruct_parameters(k, rho, delta, cell, resolution, method, max_memory);
        p.vertex_normals = vertex_normals;
        check_range(tile_size, "tile_size", true);
        TilingOptions options;
        options.reconstruction = p.options(false);
        options.tile_size = tile_size;
        options.statistics_points = statistics_points;
        const PointPass pass = pass_over_file(input, read_options(format, columns, skip_invalid));
        return plan_summary(run_tile_step(std::nullopt, [&] { return plan_tiles(pass, options, work_dir); }));
      },
      py::arg("input"), py::arg("work_dir"), py::arg("method") = "refined", py::arg("k") = py::none(),
      py::arg("rho") = py::none(), py::arg("delta") = py::none(), py::arg("cell") = py::none(),
      py::arg("resolution") = py::none(), py::arg("tile_size") = 0.0, py::arg("max_memory") = py::none(),
      py::arg("statistics_points") = 0, py::arg("format") = py::none(), py::arg("columns") = py::none(),
      py::arg("skip_invalid") = false, py::arg("vertex_normals") = false);
  m.def(
      "_tiles_count",
      [](const std::filesystem::path& work_dir) {
        return run_tile_step(std::nullopt, [&] { return read_tile_plan(work_dir).tiles.size(); });
      },
      py::arg("work_dir"));
  m.def(
      "_tiles_orient",
      [](const std::filesystem::path& work_dir, std::size_t tile, std::optional<int> threads) {
        return orientation_summary(run_tile_step(threads, [&] { return orient_tile(work_dir, tile); }));
      },
      py::arg("work_dir"), py::arg("tile"), py::arg("threads") = py::none());
  m.def(
      "_tiles_reconcile",
      [](const std::filesystem::path& work_dir) {
        return reconciliation_summary(run_tile_step(std::nullopt, [&] { return reconcile_tiles(work_dir); }));
      },
      py::arg("work_dir"));
  m.def(
      "_tiles_contour",
      [](const std::filesystem::path& work_dir, std::size_t tile, std::optional<int> threads) {
        return contour_summary(run_tile_step(threads, [&] { return contour_tile(work_dir, tile); }));
      },
      py::arg("work_dir"), py::arg("tile"), py::arg("threads") = py::none());
  m.def(
      "_tiles_stitch",
      [](const std::filesystem::path& work_dir, const std::filesystem::path& output) {
        return mesh_summary(run_tile_step(std::nullopt, [&] { return stitch_tiles(work_dir, output); }));
      },
      py::arg("work_dir"), py::arg("output"));
  bind_tile_workspace(m);
}

}  // namespace
}  // namespace recon::python

PYBIND11_MODULE(_recon, m) {
  using namespace recon;
  using namespace recon::python;
  m.doc() = "The compiled part of recon (see the recon package for the documented interface).";
  m.attr("__version__") = std::string(version());  // recon/core/version.h: the program's and the wheel's too
  py::register_exception<ResourceLimitError>(m, "ResourceLimitError", PyExc_MemoryError);
  py::register_exception_translator(translate);
  bind_point_cloud(m);
  bind_mesh(m);
  bind_files(m);
  bind_runs(m);
  bind_tiles(m);
}
