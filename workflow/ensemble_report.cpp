#include "workflow/ensemble_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "postproc/output.hpp"
#include "postproc/slope_geometry.hpp"

namespace talus::workflow {
namespace {

constexpr const char* kHeader =
    "realisation,seed,solved,failed,runout_m,crest_retreat_m,failed_area_m2,travel_angle_deg,time_to_rest_s,"
    "crown_x_m,tip_x_m,steps,simulated_time_s";
constexpr std::size_t kColumns = 14;  // and one per field
constexpr const char* kPreamble = "# talus ensemble, inputs ";

std::string number(double value) {
  if (!std::isfinite(value)) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}
std::string number(const std::optional<double>& value) { return value ? number(*value) : ""; }

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// A whole field as a number: false when it is not one. Empty is NaN when `empty_ok`.
bool parse(const std::string& text, double& value, bool empty_ok) {
  if (text.empty()) {
    value = std::nan("");
    return empty_ok;
  }
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(value);
}

}  // namespace

std::optional<RealisationRow> parse_csv_line(const std::string& line, std::size_t fields, bool fos) {
  const std::vector<std::string> f = split(line);
  if (f.size() != kColumns + fields + (fos ? 1 : 0)) return std::nullopt;
  RealisationRow row;
  double index, seed, solved, failed, travel, rest, steps;
  if (!parse(f[0], index, false) || !parse(f[1], seed, false) || !parse(f[2], solved, false) ||
      !parse(f[3], failed, false) || !parse(f[4], row.runout, false) || !parse(f[5], row.crest_retreat, false) ||
      !parse(f[6], row.failed_area, false) || !parse(f[7], travel, true) || !parse(f[8], rest, true) ||
      !parse(f[9], row.crown_x, true) || !parse(f[10], row.tip_x, true) || !parse(f[11], steps, false) ||
      !parse(f[12], row.simulated_time, false))
    return std::nullopt;
  if (seed < 0 || seed != std::floor(seed) || (solved != 0 && solved != 1) || (failed != 0 && failed != 1))
    return std::nullopt;
  row.index = static_cast<long>(index);
  row.seed = static_cast<unsigned long long>(seed);
  row.solved = solved == 1;
  row.failed = failed == 1;
  if (std::isfinite(travel)) row.travel_angle = travel;
  if (std::isfinite(rest)) row.time_to_rest = rest;
  row.steps = static_cast<long>(steps);
  for (std::size_t k = 0; k < fields; ++k) {
    double mean;
    if (!parse(f[13 + k], mean, true)) return std::nullopt;
    row.field_means.push_back(mean);
  }
  if (fos) {
    double factor;
    if (!parse(f[13 + fields], factor, true)) return std::nullopt;
    if (std::isfinite(factor)) row.fos = factor;
  }
  row.message = f.back();
  return row;
}

namespace {

std::string hex(std::uint64_t value) {
  std::ostringstream out;
  out << std::hex << std::setw(16) << std::setfill('0') << value;
  return out.str();
}

// A curve's points (under `at_key`), its probabilities and their 95 % band, as arrays.
void write_curve(postproc::JsonWriter& json, const std::string& at_key, const Curve& curve) {
  for (const auto& [name, values] : {std::pair{at_key.c_str(), &curve.at}, std::pair{"probability", &curve.probability},
                                     std::pair{"lower_95", &curve.lower}, std::pair{"upper_95", &curve.upper}}) {
    json.key(name).begin_array();
    for (double v : *values) json.value(v);
    json.end_array();
  }
}

}  // namespace

std::string csv_preamble(std::uint64_t inputs, const std::vector<std::string>& fields, bool fos) {
  std::string header = kHeader;
  for (const std::string& name : fields) header += ",mean_" + name;
  if (fos) header += ",fos";
  return kPreamble + hex(inputs) + "\n" + header + ",message\n";
}

std::string csv_line(const RealisationRow& r, bool fos) {
  // The message is free text: kept on its line and in its column.
  std::string message = r.message;
  std::replace_if(message.begin(), message.end(), [](char c) { return c == ',' || c == '\n' || c == '\r'; }, ';');
  std::ostringstream line;
  line << r.index << ',' << r.seed << ',' << (r.solved ? 1 : 0) << ',' << (r.failed ? 1 : 0) << ',' << number(r.runout)
       << ',' << number(r.crest_retreat) << ',' << number(r.failed_area) << ',' << number(r.travel_angle) << ','
       << number(r.time_to_rest) << ',' << number(r.crown_x) << ',' << number(r.tip_x) << ',' << r.steps << ','
       << number(r.simulated_time) << ',';
  for (double mean : r.field_means) line << number(mean) << ',';
  if (fos) line << number(r.fos) << ',';
  line << message << '\n';
  return line.str();
}

std::map<std::uint64_t, RealisationRow> read_rows(const std::string& path, std::uint64_t inputs,
                                                  const std::vector<std::string>& fields, long& dropped, bool fos) {
  dropped = 0;
  std::map<std::uint64_t, RealisationRow> rows;
  std::ifstream in(path, std::ios::binary);
  if (!in) return rows;
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string preamble = csv_preamble(inputs, fields, fos);
  if (text.compare(0, preamble.size(), preamble) != 0) return rows;
  std::size_t start = preamble.size();
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) {  // the last line, never finished
      ++dropped;
      break;
    }
    const auto row = parse_csv_line(text.substr(start, end - start), fields.size(), fos);
    if (row) rows[row->seed] = *row;
    else ++dropped;
    start = end + 1;
  }
  return rows;
}

void write_rows(const std::string& path, std::uint64_t inputs, const std::vector<std::string>& fields,
                const std::vector<RealisationRow>& rows, bool fos) {
  std::vector<const RealisationRow*> sorted;
  for (const auto& row : rows) sorted.push_back(&row);
  std::sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->seed < b->seed; });
  std::string text = csv_preamble(inputs, fields, fos);
  for (const RealisationRow* row : sorted) text += csv_line(*row, fos);
  write_text_atomically(path, text);
}

std::string ensemble_json(const EnsembleModel& ensemble, const EnsembleRun& run, const std::vector<RealisationRow>& rows) {
  std::vector<RealisationRow> solved;
  for (const auto& row : rows)
    if (row.solved) solved.push_back(row);
  const std::size_t n = solved.size();
  const auto failed = static_cast<std::size_t>(std::count_if(solved.begin(), solved.end(), [](auto& r) { return r.failed; }));
  std::vector<double> runout;
  for (const auto& row : solved) runout.push_back(row.runout);
  const postproc::Mirror& mirror = ensemble.slope.mirror;
  // The ground: the slope's surface, and beyond its toe the level of its lowest point out to the
  // domain's end (where the debris runs out); scene frame, x increasing.
  postproc::Polyline ground = ensemble.slope.profile.surface;
  double far = ground.back().x();
  for (const auto& node : ensemble.model.nodes) far = std::max(far, mirror.x(node.x()));
  if (far > ground.back().x()) ground.emplace_back(far, ground.back().y());
  ground = mirror.polyline(ground);

  postproc::JsonWriter json;
  json.begin_object();
  json.key("scene").value(ensemble.scene.name);
  json.key("scene_file").value(ensemble.scene.path);
  json.key("seed").value(static_cast<double>(run.seed));
  json.key("realisations").value(run.realisations);
  json.key("solved").value(static_cast<long>(n));
  json.key("solver_errors").value(static_cast<long>(rows.size() - n));
  json.key("random_fields").begin_array();
  for (const RandomField& field : ensemble.scene.random) json.value(field.name + ": " + field.material + "." + field.parameter);
  json.end_array();
  json.key("failure_criterion").begin_object();
  std::ostringstream criterion;
  criterion << "a realisation fails when its sliding mass (the particles of the analysed bodies displaced more than "
               "the sliding threshold, post.sliding_threshold x H) holds at least "
            << kFailedAreaFraction * 100 << " % of their area";
  json.key("rule").value(criterion.str());
  json.key("sliding_threshold_m").value(ensemble.sliding_threshold);
  json.key("slope_height_m").value(ensemble.slope.profile.height);
  json.key("min_failed_area_m2").value(ensemble.min_failed_area);
  json.key("ground_area_m2").value(ensemble.ground_area);
  json.end_object();
  json.key("failed").value(static_cast<long>(failed));
  if (n > 0) {
    const Interval band = wilson_interval(failed, n);
    json.key("probability_of_failure").value(static_cast<double>(failed) / static_cast<double>(n));
    json.key("probability_of_failure_95").begin_array().value(band.lower).value(band.upper).end_array();
    json.key("runout_note").value("runout from the initial toe, 0 for a realisation that did not fail");
    json.key("runout_quantiles_m").begin_object();
    for (const auto& [name, q] : {std::pair{"P50", 0.5}, std::pair{"P90", 0.9}, std::pair{"P95", 0.95}})
      json.key(name).value(quantile(runout, q));
    json.end_object();
    const double largest = *std::max_element(runout.begin(), runout.end());
    const Curve curve = exceedance(runout, evenly(0, largest > 0 ? 1.05 * largest : 1.0, 101));
    json.key("exceedance").begin_object();
    write_curve(json, "runout_m", curve);
    json.end_object();
    const Curve along = reach(solved, evenly(ground.front().x(), ground.back().x(), 201));
    json.key("reach").begin_object();
    json.key("rule").value("the fraction of realisations in which the point lies between the failure's crown and the "
                           "deposit's tip, along the slope's surface and beyond its toe to the domain's end");
    json.key("ground_y_m").begin_array();
    for (double x : along.at) json.value(postproc::surface_height(ensemble.slope.profile.surface, mirror.x(x)));
    json.end_array();
    write_curve(json, "x_m", along);
    json.end_object();
  }
  if (run.fos_tolerance) {
    // --fos: the factors of safety over the realisations that have one, and how the verdict F < 1
    // compares with the runout's failure criterion.
    std::vector<double> factors;
    long both = 0, only_fos = 0, only_runout = 0, neither = 0;
    for (const auto& row : rows) {
      if (!row.fos) continue;
      factors.push_back(*row.fos);
      if (!row.solved) continue;
      const bool below = *row.fos < 1;
      (row.failed ? (below ? both : only_runout) : (below ? only_fos : neither))++;
    }
    json.key("fos").begin_object();
    json.key("rule").value("each realisation's factor of safety by strength reduction, talus fos's search on its "
                           "fields (docs/fos.md): the middle of the final bracket");
    json.key("tolerance").value(*run.fos_tolerance);
    json.key("count").value(static_cast<long>(factors.size()));
    json.key("errors").value(static_cast<long>(rows.size() - factors.size()));
    if (!factors.empty()) {
      const double count = static_cast<double>(factors.size());
      double mean = 0;
      for (double f : factors) mean += f / count;
      double square = 0;
      for (double f : factors) square += (f - mean) * (f - mean);
      const auto below = static_cast<std::size_t>(std::count_if(factors.begin(), factors.end(), [](double f) { return f < 1; }));
      const Interval band = wilson_interval(below, factors.size());
      json.key("mean").value(mean);
      json.key("std").value(factors.size() > 1 ? std::sqrt(square / (count - 1)) : std::nan(""));
      json.key("min").value(*std::min_element(factors.begin(), factors.end()));
      json.key("max").value(*std::max_element(factors.begin(), factors.end()));
      json.key("quantiles").begin_object();
      for (const auto& [name, q] : {std::pair{"P05", 0.05}, std::pair{"P50", 0.5}, std::pair{"P95", 0.95}})
        json.key(name).value(quantile(factors, q));
      json.end_object();
      json.key("below_1").value(static_cast<long>(below));
      json.key("probability_below_1").value(static_cast<double>(below) / count);
      json.key("probability_below_1_95").begin_array().value(band.lower).value(band.upper).end_array();
    }
    json.key("against_runout_criterion").begin_object();
    json.key("failed_and_below_1").value(both);
    json.key("failed_but_not_below_1").value(only_runout);
    json.key("below_1_but_not_failed").value(only_fos);
    json.key("neither").value(neither);
    json.end_object();
    json.end_object();
  }
  json.key("ground_surface").value(ground);
  json.key("toe_m").begin_array().value(mirror.x(ensemble.slope.profile.toe.x())).value(ensemble.slope.profile.toe.y()).end_array();
  json.key("timing").begin_object();
  json.key("ranks").value(static_cast<long>(run.ranks));
  json.key("jobs").value(static_cast<long>(run.jobs));
  json.key("mesh_s").value(run.mesh_seconds);
  json.key("realisations_timed").value(run.timed);
  json.key("fields_s").value(run.field_seconds);
  json.key("solve_s").value(run.solve_seconds);
  json.key("post_s").value(run.post_seconds);
  if (run.fos_tolerance) json.key("fos_s").value(run.fos_seconds);
  json.key("record_s").value(run.record_seconds);
  json.key("wall_s").value(run.wall_seconds);
  json.key("overhead_of_solve").value(run.solve_seconds > 0 ? (run.field_seconds + run.post_seconds + run.record_seconds) / run.solve_seconds
                                                            : std::nan(""));
  json.key("realisations_per_hour").value(run.wall_seconds > 0 ? 3600.0 * static_cast<double>(run.timed) / run.wall_seconds
                                                               : std::nan(""));
  json.end_object();
  json.end_object();
  return json.text();
}

}  // namespace talus::workflow
