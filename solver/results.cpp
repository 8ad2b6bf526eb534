#include "solver/results.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "common/model_io.hpp"

namespace talus::solver {

ResultsWriter::ResultsWriter(const std::string& out_dir, const Model& model)
    : path_((std::filesystem::path(out_dir) / "results.h5").string()),
      xdmf_path_((std::filesystem::path(out_dir) / "results.xdmf").string()),
      particles_(model.particle_count()),
      file_(h5::File::create(path_)) {
  write_format_tag(file_, "talus-results", kResultsFormatVersion);
  write_metadata(file_, model);
  const hsize_t n = particles_;
  std::vector<double> flat;
  for (const auto& x : model.position) flat.insert(flat.end(), {x.x(), x.y()});
  h5::write(file_, "particles/initial_position", flat, {n, 2});
  h5::write(file_, "particles/body", model.body, {n});
  h5::write(file_, "particles/mass", model.mass, {n});
  h5::write(file_, "particles/volume", model.volume, {n});
  time_set_ = h5::Appendable(file_, "frames/time", {}, H5T_NATIVE_DOUBLE, 256);
  position_ = h5::Appendable(file_, "frames/position", {n, 2});
  velocity_ = h5::Appendable(file_, "frames/velocity", {n, 2});
  stress_ = h5::Appendable(file_, "frames/stress", {n, 4});
  plastic_strain_ = h5::Appendable(file_, "frames/plastic_strain", {n});
  history_time_ = h5::Appendable(file_, "history/time", {}, H5T_NATIVE_DOUBLE, 1024);
  history_kinetic_ = h5::Appendable(file_, "history/kinetic_energy", {}, H5T_NATIVE_DOUBLE, 1024);
  history_potential_ = h5::Appendable(file_, "history/potential_energy", {}, H5T_NATIVE_DOUBLE, 1024);
  history_strain_ = h5::Appendable(file_, "history/strain_energy", {}, H5T_NATIVE_DOUBLE, 1024);
  history_particle_kinetic_ = h5::Appendable(file_, "history/particle_kinetic_energy", {}, H5T_NATIVE_DOUBLE, 1024);
  h5::set_attribute(file_, "/", "particles", static_cast<int64_t>(n));
  h5::set_attribute(file_, "/", "steps", static_cast<int64_t>(0));
  h5::set_attribute(file_, "/", "loop_seconds", 0.0);
  h5::set_attribute(file_, "/", "complete", static_cast<int64_t>(0));
  file_.flush();
}

void ResultsWriter::write_frame(const Simulation& sim) {
  const Particles& P = sim.particles;
  const std::size_t n = particles_;
  // Frames are in the model's particle order (the solver keeps its own, sorted, order).
  auto gather = [&](int width, auto value) {
    scratch_.assign(n * width, 0.0);
    for (std::size_t p = 0; p < n; ++p)
      for (int k = 0; k < width; ++k) scratch_[P.id[p] * width + k] = value(p, k);
    return scratch_.data();
  };
  time_set_.append(&sim.time);
  position_.append(gather(2, [&](std::size_t p, int k) { return P.x[p][k]; }));
  const std::vector<Vec2> velocity = grid_velocity_at_particles(sim);
  velocity_.append(gather(2, [&](std::size_t p, int k) { return velocity[p][k]; }));
  stress_.append(gather(4, [&](std::size_t p, int k) { return P.sigma[p][k]; }));
  plastic_strain_.append(gather(1, [&](std::size_t p, int) { return P.eps_p[p]; }));
  time_.push_back(sim.time);
  flush_history();
  h5::set_attribute(file_, "/", "steps", static_cast<int64_t>(sim.steps));
  file_.flush();
  write_xdmf();
}

void ResultsWriter::record_history(const Simulation& sim, const Energies& energy) {
  pending_time_.push_back(sim.time);
  pending_kinetic_.push_back(energy.grid_kinetic);
  pending_particle_kinetic_.push_back(energy.kinetic);
  pending_potential_.push_back(energy.potential);
  pending_strain_.push_back(energy.strain);
}

void ResultsWriter::flush_history() {
  const hsize_t rows = pending_time_.size();
  history_time_.append(pending_time_.data(), rows);
  history_kinetic_.append(pending_kinetic_.data(), rows);
  history_potential_.append(pending_potential_.data(), rows);
  history_strain_.append(pending_strain_.data(), rows);
  history_particle_kinetic_.append(pending_particle_kinetic_.data(), rows);
  pending_time_.clear();
  pending_kinetic_.clear();
  pending_potential_.clear();
  pending_strain_.clear();
  pending_particle_kinetic_.clear();
}

void ResultsWriter::finish(long steps, double loop_seconds, bool complete) {
  flush_history();
  h5::set_attribute(file_, "/", "steps", static_cast<int64_t>(steps));
  h5::set_attribute(file_, "/", "loop_seconds", loop_seconds);
  h5::set_attribute(file_, "/", "complete", static_cast<int64_t>(complete));
  file_.flush();
  file_.close();
  write_xdmf();
}

void ResultsWriter::write_xdmf() const {
  // A temporal collection of polyvertex grids whose data are hyperslabs of the frame datasets.
  const std::string h5_name = std::filesystem::path(path_).filename().string();
  const std::size_t n = particles_;
  const std::string temporary = xdmf_path_ + ".tmp";
  {
    std::ofstream out(temporary);
    out << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
        << "<Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    auto slab = [&](std::size_t frame, const std::string& set, int width, int component) {
      std::ostringstream s;
      const bool one = component >= 0;
      const int columns = one ? 1 : width;
      s << "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" << n << (columns > 1 ? " " + std::to_string(columns) : "")
        << "\" Type=\"HyperSlab\">\n"
        << "<DataItem Dimensions=\"3 " << (width > 1 ? 3 : 2) << "\" Format=\"XML\">" << frame << " 0"
        << (width > 1 ? " " + std::to_string(one ? component : 0) : "") << " 1 1" << (width > 1 ? " 1" : "") << " 1 "
        << n << (width > 1 ? " " + std::to_string(columns) : "") << "</DataItem>\n"
        << "<DataItem Dimensions=\"" << time_.size() << " " << n << (width > 1 ? " " + std::to_string(width) : "")
        << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5_name << ":/frames/" << set
        << "</DataItem>\n</DataItem>\n";
      return s.str();
    };
    for (std::size_t f = 0; f < time_.size(); ++f) {
      out << "<Grid Name=\"frame " << f << "\" GridType=\"Uniform\">\n<Time Value=\"" << time_[f] << "\"/>\n"
          << "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\"/>\n"
          << "<Geometry GeometryType=\"XY\">\n" << slab(f, "position", 2, -1) << "</Geometry>\n";
      out << "<Attribute Name=\"velocity_x\" AttributeType=\"Scalar\" Center=\"Node\">\n" << slab(f, "velocity", 2, 0)
          << "</Attribute>\n";
      out << "<Attribute Name=\"velocity_y\" AttributeType=\"Scalar\" Center=\"Node\">\n" << slab(f, "velocity", 2, 1)
          << "</Attribute>\n";
      const char* stress_names[] = {"stress_xx", "stress_yy", "stress_zz", "stress_xy"};
      for (int k = 0; k < 4; ++k)
        out << "<Attribute Name=\"" << stress_names[k] << "\" AttributeType=\"Scalar\" Center=\"Node\">\n"
            << slab(f, "stress", 4, k) << "</Attribute>\n";
      out << "<Attribute Name=\"plastic_strain\" AttributeType=\"Scalar\" Center=\"Node\">\n"
          << slab(f, "plastic_strain", 1, -1) << "</Attribute>\n";
      out << "</Grid>\n";
    }
    out << "</Grid>\n</Domain>\n</Xdmf>\n";
  }
  std::filesystem::rename(temporary, xdmf_path_);
}

}  // namespace talus::solver
