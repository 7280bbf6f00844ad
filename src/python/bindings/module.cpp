// The pybind11 glue of the Python module `lidarscout` (built as lidarscout/_lidarscout, beside its
// Python side python/lidarscout/): arguments turned into the python stage's requests, its work run
// with the GIL released, its point tables and rasters handed to numpy without a copy, and
// lidarscout::Error raised as lidarscout.Error (file, offset, cause). Nothing here reads or decides.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "python/dem_array.hpp"
#include "python/open.hpp"
#include "python/overview.hpp"
#include "python/point_table.hpp"
#include "python/region_read.hpp"

namespace py = pybind11;

namespace lidarscout::python {
namespace {

// Text from the data (names, causes) as str, bytes that are not UTF-8 replaced.
py::str text(const std::string& s) {
    return py::reinterpret_steal<py::str>(PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "replace"));
}
// A path as Python's os.fsdecode gives it (bytes that are not UTF-8 kept as surrogates).
py::str path_text(const std::string& s) {
    const auto size = static_cast<Py_ssize_t>(s.size());
    return py::reinterpret_steal<py::str>(PyUnicode_DecodeFSDefaultAndSize(s.data(), size));
}
py::object text_or_none(const std::string& s) { return s.empty() ? py::object(py::none()) : py::object(text(s)); }

void raise_as_python(const Error& e) {
    const py::object cls = py::module_::import("lidarscout._error").attr("Error");
    const py::object offset = e.offset() ? py::object(py::int_(*e.offset())) : py::object(py::none());
    const py::object file = e.file().empty() ? py::object(py::none()) : py::object(path_text(e.file()));
    const py::object error = cls(text(e.what()), file, offset, text(e.cause()));
    PyErr_SetObject(cls.ptr(), error.ptr());
}

// A str, a path-like, or an iterable of them -> the strings.
std::vector<std::string> strings(const py::handle& v) {
    const py::module_ os = py::module_::import("os");
    if (py::isinstance<py::str>(v) || py::hasattr(v, "__fspath__")) return {os.attr("fsencode")(v).cast<std::string>()};
    std::vector<std::string> out;
    for (const auto item : v) out.push_back(os.attr("fsencode")(item).cast<std::string>());
    return out;
}

// None -> "", a str as it is, a number as its text, an iterable as its items' text joined by `sep`.
std::string option_text(const py::handle& v, const char* sep) {
    if (v.is_none()) return "";
    if (py::isinstance<py::str>(v)) return v.cast<std::string>();
    if (!py::isinstance<py::iterable>(v)) return py::str(v).cast<std::string>();
    std::string out;
    for (const auto item : v) out += (out.empty() ? "" : sep) + py::str(item).cast<std::string>();
    return out;
}

std::optional<std::array<double, 4>> bounds_of(const py::handle& v, const char* stage) {
    if (v.is_none()) return std::nullopt;
    const auto b = v.cast<std::vector<double>>();
    if (b.size() != 4) throw Error(std::string(stage) + ": bounds expects four numbers: xmin, ymin, xmax, ymax");
    return std::array<double, 4>{b[0], b[1], b[2], b[3]};
}

py::dtype points_dtype(PointFields f) {
    py::list names, formats, offsets;
    const auto add = [&](const char* name, const char* format, std::size_t offset) {
        names.append(name), formats.append(format), offsets.append(offset);
    };
    add("x", "<f8", offsetof(PointRecord, x)), add("y", "<f8", offsetof(PointRecord, y));
    add("z", "<f8", offsetof(PointRecord, z)), add("intensity", "<u2", offsetof(PointRecord, intensity));
    add("return_number", "u1", offsetof(PointRecord, return_number));
    add("number_of_returns", "u1", offsetof(PointRecord, number_of_returns));
    add("classification", "u1", offsetof(PointRecord, classification));
    if (f.gps_time) add("gps_time", "<f8", offsetof(PointRecord, gps_time));
    if (f.rgb) {
        add("red", "<u2", offsetof(PointRecord, red)), add("green", "<u2", offsetof(PointRecord, green));
        add("blue", "<u2", offsetof(PointRecord, blue));
    }
    add("tile", "<u4", offsetof(PointRecord, tile));
    return py::dtype(names, formats, offsets, sizeof(PointRecord));
}

// The table as a structured array that owns it (no copy).
py::array points_array(PointTable table, PointFields fields) {
    auto owner = std::make_unique<PointTable>(std::move(table));
    const py::dtype dtype = points_dtype(fields);
    const std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(owner->size())};
    const std::vector<py::ssize_t> strides{static_cast<py::ssize_t>(sizeof(PointRecord))};
    PointTable* points = owner.get();
    const py::capsule base(owner.release(), [](void* p) { delete static_cast<PointTable*>(p); });
    return py::array(dtype, shape, strides, points->data(), base);
}

py::list error_list(const std::vector<ErrorRecord>& errors) {
    py::list out;
    for (const auto& e : errors) {
        out.append(py::dict(py::arg("file") = e.file.empty() ? py::object(py::none()) : py::object(path_text(e.file)),
                            py::arg("offset") = e.offset ? py::object(py::int_(*e.offset)) : py::object(py::none()),
                            py::arg("cause") = text(e.cause)));
    }
    return out;
}

// dem's options (raster/dem_options.hpp) from keywords named as dem's options are (--max-edge: max_edge,
// --from: source, --memory: memory in bytes); an unknown keyword is an Error naming the known ones.
double dem_number(const py::handle& v, const std::string& name) {
    try {
        return py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>();
    } catch (const py::error_already_set&) {
        throw Error("dem: " + name + " expects a number, not '" + py::str(v).cast<std::string>() + "'");
    }
}

raster::DemOptions dem_options(const py::kwargs& kwargs) {
    raster::DemOptions o;
    const auto ground = [&](const py::handle& value, const std::string& name, double& field, const char* option) {
        field = dem_number(value, name);
        o.ground_options.emplace_back(option);
    };
    for (const auto& [key, value] : kwargs) {
        const std::string k = key.cast<std::string>();
        if (value.is_none()) continue;
        if (k == "texel") o.texel = dem_number(value, k);
        else if (k == "bounds") o.bounds = value.cast<std::vector<double>>();
        else if (k == "source") o.from = option_text(value, ",");
        else if (k == "method") o.method = option_text(value, ",");
        else if (k == "product") o.product = option_text(value, ",");
        else if (k == "classes") o.classes = option_text(value, ",");
        else if (k == "returns") o.returns = option_text(value, ",");
        else if (k == "intensity") o.intensity = option_text(value, "-");
        else if (k == "radius") o.radius = dem_number(value, k);
        else if (k == "power") o.power = dem_number(value, k);
        else if (k == "max_edge") o.max_edge = dem_number(value, k);
        else if (k == "ground") o.ground = option_text(value, ",");
        else if (k == "ground_cell") ground(value, k, o.ground_params.cell_m, "--ground-cell");
        else if (k == "ground_slope") ground(value, k, o.ground_params.slope, "--ground-slope");
        else if (k == "ground_window") ground(value, k, o.ground_params.window_m, "--ground-window");
        else if (k == "ground_threshold") ground(value, k, o.ground_params.threshold_m, "--ground-threshold");
        else if (k == "model") o.model = strings(value).at(0);
        else if (k == "memory") o.memory = value.cast<std::uint64_t>();
        else if (k == "threads") o.threads = value.cast<unsigned>();
        else throw Error("dem: unknown option '" + k + "' (the options are texel, bounds, source, method, product, "
                         "classes, returns, intensity, radius, power, max_edge, ground, ground_cell, ground_slope, "
                         "ground_window, ground_threshold, model, memory, threads)");
    }
    return o;
}

py::tuple blocks(const raster::BlockRange& b) { return py::make_tuple(b.x0, b.y0, b.x1, b.y1); }
py::tuple window(const raster::DemGrid::Window& w) { return py::make_tuple(w.col, w.row, w.width, w.height); }

class PyDataset;

// ds.iter_read(...): tables of at most `batch` points, the next one read while Python works on this one.
class PyRegionStream {
public:
    PyRegionStream(std::shared_ptr<const dataset::Dataset> ds, RegionQuery query, unsigned threads, std::size_t batch)
        : stream_(std::make_unique<RegionStream>(ds, std::move(query), threads, batch)),
          fields_(point_fields(*ds, stream_->tiles())) {}
    py::array next() {
        if (!stream_) throw py::stop_iteration();
        std::optional<PointTable> table;
        {
            const py::gil_scoped_release nogil;
            table = stream_->next();
        }
        if (!table) throw py::stop_iteration();
        return points_array(std::move(*table), fields_);
    }
    void close() {
        const py::gil_scoped_release nogil;
        stream_.reset();
    }

private:
    std::unique_ptr<RegionStream> stream_;
    PointFields fields_;
};

class PyDataset {
public:
    explicit PyDataset(dataset::Dataset ds) : ds_(std::make_shared<const dataset::Dataset>(std::move(ds))) {}

    py::list tiles() const {
        py::list out;
        for (const auto& t : ds_->tiles) {
            const auto& crs = t.tile.crs();
            out.append(py::dict(py::arg("path") = path_text(t.tile.path()),
                                py::arg("count") = t.tile.header.point_count, py::arg("bounds") = bounds(t.bounds_m),
                                py::arg("crs") = py::dict(py::arg("epsg") = crs.epsg, py::arg("vertical_epsg") =
                                                          crs.vertical_epsg, py::arg("name") = text_or_none(crs.name)),
                                py::arg("point_format") = t.tile.header.point_format));
        }
        return out;
    }
    std::uint64_t point_count() const { return ds_->point_count; }
    py::tuple dataset_bounds() const { return bounds(ds_->bounds_m); }
    py::dict crs() const {
        const CrsSummary s = crs_summary(ds_->frame.crs);
        return py::dict(py::arg("wkt") = text_or_none(s.wkt), py::arg("epsg") = s.epsg ? py::object(py::int_(s.epsg))
                                                                                        : py::object(py::none()),
                        py::arg("vertical_epsg") = s.vertical_epsg ? py::object(py::int_(s.vertical_epsg))
                                                                   : py::object(py::none()),
                        py::arg("name") = text_or_none(s.name), py::arg("definition") = text_or_none(s.definition),
                        py::arg("geographic") = ds_->frame.geographic);
    }
    py::list skipped() const {
        py::list out;
        for (const auto& s : ds_->skipped) out.append(py::dict(py::arg("path") = path_text(s.path),
                                                               py::arg("error") = text(s.error)));
        return out;
    }
    py::list warnings() const {
        py::list out;
        for (const auto& m : ds_->warnings.messages()) out.append(text(m));
        return out;
    }
    py::list last_skipped() const { return error_list(last_skipped_); }

    py::array overview(unsigned threads) {
        Overview o = [&] {
            const py::gil_scoped_release nogil;
            return read_overview(*ds_, threads);
        }();
        last_skipped_ = std::move(o.skipped);
        return points_array(std::move(o.points), point_fields(*ds_));
    }

    py::array read(const py::object& bounds, const py::object& polygon, const py::object& classes,
                   const py::object& returns, const py::object& intensity, unsigned threads) {
        const RegionQuery q = query(bounds, polygon, classes, returns, intensity, "read");
        RegionRead r = [&] {
            const py::gil_scoped_release nogil;
            return read_region(*ds_, q, threads);
        }();
        last_skipped_ = std::move(r.stats.skipped);
        return points_array(std::move(r.points), point_fields(*ds_, r.stats.tiles_touched));
    }

    PyRegionStream iter_read(const py::object& bounds, const py::object& polygon, const py::object& classes,
                             const py::object& returns, const py::object& intensity, unsigned threads,
                             std::size_t batch) {
        return PyRegionStream(ds_, query(bounds, polygon, classes, returns, intensity, "iter_read"), threads, batch);
    }

    py::tuple dem(const py::kwargs& options) {
        const raster::DemOptions o = dem_options(options);
        auto raster = std::make_unique<raster::FloatRaster>([&] {
            const py::gil_scoped_release nogil;
            return make_dem_raster(*ds_, o);
        }());
        const auto& g = raster->geotransform;
        const py::tuple geotransform = py::make_tuple(g[0], g[1], g[2], g[3], g[4], g[5]);
        const std::vector<py::ssize_t> shape{raster->height, raster->width};
        float* values = raster->values.data();
        const py::capsule base(raster.release(), [](void* p) { delete static_cast<raster::FloatRaster*>(p); });
        return py::make_tuple(py::array_t<float>(shape, values, base), geotransform);
    }

    py::dict dem_plan(int count, const py::kwargs& options) {
        const raster::DemOptions o = dem_options(options);
        const raster::DemPlan plan = [&] {
            const py::gil_scoped_release nogil;
            return plan_dem(*ds_, o, count);
        }();
        py::list pieces;
        for (const raster::DemPiece& p : plan.pieces) {
            pieces.append(py::dict(py::arg("index") = p.index, py::arg("blocks") = blocks(p.blocks),
                                   py::arg("window") = window(p.window),
                                   py::arg("points") = static_cast<long long>(std::llround(p.points)),
                                   py::arg("memory_estimate_bytes") = p.memory_estimate));
        }
        const raster::DemGrid& g = plan.grid;
        return py::dict(py::arg("width") = g.width, py::arg("height") = g.height, py::arg("texel_m") = g.texel_m,
                        py::arg("block_texels") = g.block, py::arg("blocks") = plan.blocks,
                        py::arg("tiles") = ds_->tiles.size(), py::arg("points") = plan.points,
                        py::arg("pieces") = pieces);
    }

    py::dict dem_block(int index, int count, const py::object& output, const py::kwargs& options) {
        const raster::DemOptions o = dem_options(options);
        const std::string path = strings(output).at(0);
        const DemBlock made = [&] {
            const py::gil_scoped_release nogil;
            return make_dem_block(*ds_, o, index, count, path);
        }();
        const raster::DemResult& d = made.result;
        py::dict outputs;
        for (std::size_t i = 0; i < made.names.size(); ++i) outputs[text(made.names[i])] = path_text(d.outputs[i]);
        const raster::DemGrid& g = d.grid;
        const py::dict block(py::arg("index") = index, py::arg("count") = count,
                             py::arg("blocks") = blocks(g.selected_blocks()), py::arg("grid_width") = g.width,
                             py::arg("grid_height") = g.height, py::arg("window") = window(g.window()));
        return py::dict(py::arg("outputs") = outputs, py::arg("block") = block, py::arg("points_read") = d.points_read,
                        py::arg("points_used") = d.points_used, py::arg("points_skipped") = d.points_skipped,
                        py::arg("skipped") = error_list(d.skipped),
                        py::arg("memory_estimate_bytes") = d.memory_estimate,
                        py::arg("memory_budget_bytes") = d.memory_budget, py::arg("seconds_grid") = d.seconds_grid,
                        py::arg("seconds_cog") = d.seconds_cog);
    }

private:
    // In the CRS's units (the frame's metres divided back), z in its vertical unit.
    py::tuple bounds(const dataset::Bounds& b) const {
        if (b.empty()) return py::tuple();
        const double f = ds_->frame.xy_to_metres, fz = ds_->frame.z_to_metres;
        return py::make_tuple(b.min_x / f, b.min_y / f, b.min_z / fz, b.max_x / f, b.max_y / f, b.max_z / fz);
    }
    RegionQuery query(const py::object& bounds, const py::object& polygon, const py::object& classes,
                      const py::object& returns, const py::object& intensity, const char* stage) const {
        const std::string shape = polygon.is_none() ? "" : strings(polygon).at(0);
        return region_query(bounds_of(bounds, stage), shape, option_text(classes, ","),
                            option_text(returns, ","), option_text(intensity, "-"), stage);
    }

    std::shared_ptr<const dataset::Dataset> ds_;
    std::vector<ErrorRecord> last_skipped_;
};

PyDataset open_paths(const py::object& paths, const py::object& crs, const py::object& allow_origins) {
    const std::vector<std::string> p = strings(paths);
    const std::string c = option_text(crs, ","), origins = option_text(allow_origins, ",");
    const py::gil_scoped_release nogil;
    return PyDataset(open_dataset(p, c, origins));
}

}  // namespace
}  // namespace lidarscout::python

PYBIND11_MODULE(_lidarscout, m) {
    using namespace lidarscout::python;
    m.doc() = "lidarscout's datasets, overviews, regions and rasters as numpy arrays (see the README)";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const lidarscout::Error& e) {
            raise_as_python(e);
        }
    });
    py::class_<PyRegionStream>(m, "RegionStream")
        .def("__iter__", [](PyRegionStream& s) -> PyRegionStream& { return s; }, py::return_value_policy::reference)
        .def("__next__", &PyRegionStream::next)
        .def("close", &PyRegionStream::close);
    py::class_<PyDataset>(m, "Dataset")
        .def_property_readonly("tiles", &PyDataset::tiles)
        .def_property_readonly("point_count", &PyDataset::point_count)
        .def_property_readonly("bounds", &PyDataset::dataset_bounds)
        .def_property_readonly("crs", &PyDataset::crs)
        .def_property_readonly("skipped", &PyDataset::skipped)
        .def_property_readonly("warnings", &PyDataset::warnings)
        .def_property_readonly("last_skipped", &PyDataset::last_skipped)
        .def("overview", &PyDataset::overview, py::arg("threads") = 0)
        .def("read", &PyDataset::read, py::arg("bounds") = py::none(), py::arg("polygon") = py::none(),
             py::arg("classes") = py::none(), py::arg("returns") = py::none(), py::arg("intensity") = py::none(),
             py::arg("threads") = 0)
        .def("iter_read", &PyDataset::iter_read, py::arg("bounds") = py::none(), py::arg("polygon") = py::none(),
             py::arg("classes") = py::none(), py::arg("returns") = py::none(), py::arg("intensity") = py::none(),
             py::arg("threads") = 0, py::arg("batch") = 1'000'000)
        .def("dem", &PyDataset::dem)
        .def("dem_plan", &PyDataset::dem_plan, py::arg("count"))
        .def("dem_block", &PyDataset::dem_block, py::arg("index"), py::arg("count"), py::arg("output"));
    m.def("open", &open_paths, py::arg("paths"), py::arg("crs") = py::none(), py::arg("allow_origins") = py::none());
}
