#include "solver/io/results_xdmf.hpp"

#include <iomanip>
#include <numeric>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace talus::solver {
namespace {

const char* const kStressComponents[] = {"xx", "yy", "zz", "xy"};

// One view: `columns` columns from `first_column` of frame `frame` of frames/<field>, as an
// [P] dataset (width 0) or a [P, width] one whose columns past `columns` read as 0.
struct View {
  std::string name;
  int first_column, columns, width;
};

std::vector<View> views_of(const FrameField& field) {
  if (field.name == "position") return {{field.name, 0, 2, 2}};
  if (field.width == 2) return {{field.name, 0, 2, 3}};
  if (field.width == 4) {
    std::vector<View> views;
    for (int k = 0; k < 4; ++k) views.push_back({field.name + "_" + kStressComponents[k], k, 1, 0});
    return views;
  }
  if (field.width == 1) return {{field.name, 0, 1, 0}};
  std::vector<View> views;
  for (int k = 0; k < field.width; ++k) views.push_back({field.name + "_" + std::to_string(k), k, 1, 0});
  return views;
}

std::string frame_group(std::size_t frame) { return "xdmf/" + std::to_string(frame); }

void create_view(const h5::File& file, std::size_t particles, std::size_t frame, const FrameField& field,
                 const View& view) {
  const std::string path = frame_group(frame) + "/" + view.name;
  auto check = [&](bool ok) {
    if (!ok) throw Error(located(file.path(), path, "cannot write the XDMF view (disk full?)"));
  };
  const hsize_t n = particles;
  const hsize_t source_width = field.width;
  // The source: row `frame` of frames/<name>, [F, P] or [F, P, width].
  const int source_rank = field.width == 1 ? 2 : 3;
  const hsize_t source_dims[3] = {frame + 1, n, source_width};
  const hsize_t source_start[3] = {frame, 0, static_cast<hsize_t>(view.first_column)};
  const hsize_t source_count[3] = {1, n, static_cast<hsize_t>(view.columns)};
  h5::Handle source(H5Screate_simple(source_rank, source_dims, nullptr));
  check(source.valid() &&
        H5Sselect_hyperslab(source.id(), H5S_SELECT_SET, source_start, nullptr, source_count, nullptr) >= 0);
  // The view: [P] or [P, width], its first `columns` columns mapped.
  const int rank = view.width == 0 ? 1 : 2;
  const hsize_t dims[2] = {n, static_cast<hsize_t>(view.width)};
  const hsize_t start[2] = {0, 0};
  const hsize_t count[2] = {n, static_cast<hsize_t>(view.columns)};
  h5::Handle space(H5Screate_simple(rank, dims, nullptr));
  check(space.valid() && H5Sselect_hyperslab(space.id(), H5S_SELECT_SET, start, nullptr, count, nullptr) >= 0);
  h5::Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
  const double zero = 0.0;
  const std::string source_path = "/frames/" + field.name;
  check(dcpl.valid() && H5Pset_fill_value(dcpl.id(), H5T_NATIVE_DOUBLE, &zero) >= 0 &&
        H5Pset_virtual(dcpl.id(), space.id(), ".", source_path.c_str(), source.id()) >= 0);
  h5::Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
  check(lcpl.valid() && H5Pset_create_intermediate_group(lcpl.id(), 1) >= 0);
  H5Sselect_all(space.id());
  h5::Handle dataset(
      H5Dcreate2(file.id(), path.c_str(), H5T_IEEE_F64LE, space.id(), lcpl.id(), dcpl.id(), H5P_DEFAULT));
  check(dataset.valid());
}

}  // namespace

void write_xdmf_vertices(const h5::File& file, std::size_t particles) {
  if (h5::exists(file, "xdmf/vertices")) return;
  std::vector<int32_t> vertices(particles);
  std::iota(vertices.begin(), vertices.end(), 0);
  h5::write(file, "xdmf/vertices", vertices, {particles});
}

void write_frame_views(const h5::File& file, std::size_t particles, std::size_t frame,
                       const std::vector<FrameField>& fields) {
  for (const FrameField& field : fields)
    for (const View& view : views_of(field)) create_view(file, particles, frame, field, view);
}

void drop_frame_views(const h5::File& file, std::size_t keep) {
  if (!h5::exists(file, "xdmf")) return;
  for (const std::string& name : h5::list(file, "xdmf")) {
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    if (std::stoul(name) < keep) continue;
    const std::string path = "xdmf/" + name;
    if (H5Ldelete(file.id(), path.c_str(), H5P_DEFAULT) < 0)
      throw Error(located(file.path(), path, "cannot remove the XDMF views of a dropped frame"));
  }
}

void write_xdmf_file(const std::string& xdmf_path, const std::string& h5_name, std::size_t particles,
                     const std::vector<double>& times, const std::vector<FrameField>& fields) {
  const std::string n = std::to_string(particles);
  auto item = [&](const std::string& path, const std::string& dims, bool integer) {
    return "<DataItem Dimensions=\"" + dims + "\" NumberType=\"" + (integer ? "Int" : "Float") + "\" Precision=\"" +
           (integer ? "4" : "8") + "\" Format=\"HDF\">" + h5_name + ":/" + path + "</DataItem>";
  };
  auto attribute = [&](const std::string& name, const char* type, const std::string& data) {
    return "<Attribute Name=\"" + name + "\" AttributeType=\"" + type + "\" Center=\"Node\">" + data +
           "</Attribute>\n";
  };
  write_stream_atomically(xdmf_path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
        << "<Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (std::size_t f = 0; f < times.size(); ++f) {
      const std::string group = frame_group(f) + "/";
      out << "<Grid Name=\"frame " << f << "\" GridType=\"Uniform\">\n<Time Value=\"" << std::setprecision(12)
          << times[f] << "\"/>\n"
          << "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\" NodesPerElement=\"1\">"
          << item("xdmf/vertices", n, true) << "</Topology>\n";
      out << "<Geometry GeometryType=\"XY\">" << item(group + "position", n + " 2", false) << "</Geometry>\n";
      for (const FrameField& field : fields)
        for (const View& view : views_of(field)) {
          const std::string dims = view.width == 0 ? n : n + " " + std::to_string(view.width);
          if (field.name != "position")
            out << attribute(view.name, view.width == 3 ? "Vector" : "Scalar", item(group + view.name, dims, false));
        }
      out << attribute("body", "Scalar", item("particles/body", n, true))
          << attribute("material", "Scalar", item("particles/material", n, true)) << "</Grid>\n";
    }
    out << "</Grid>\n</Domain>\n</Xdmf>\n";
  });
}

}  // namespace talus::solver
