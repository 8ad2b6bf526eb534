// The mesh-convergence workflow. Method and rule for the band: docs/converge.md.
#include "workflow/converge.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/scene/scene.hpp"
#include "postproc/figure_script.hpp"
#include "preproc/estimate.hpp"
#include "workflow/folder_lock.hpp"
#include "workflow/gci.hpp"
#include "workflow/pipeline.hpp"

namespace fs = std::filesystem;

namespace talus::workflow {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Level {
  double size = 0;  // m
  std::string folder;
  double wall_seconds = 0;  // this invocation's, for mesh, solve and post (0.0x when reused)
  double loop_seconds = kNaN;  // the solver's time loop, from results.h5
  long long particles = 0, steps = 0;
  std::vector<double> values;  // per converge_metrics(); NaN when the scene does not give it
};

std::string number_text(double value, int digits = 17) {
  std::ostringstream out;
  out << std::setprecision(digits) << value;
  return out.str();
}

// The number after "key": in our own metrics.json (postproc/output.hpp writes it), searched
// from `from`; NaN when absent or null.
double json_number(const std::string& text, const std::string& key, std::size_t from = 0) {
  const std::size_t at = text.find("\"" + key + "\"", from);
  if (at == std::string::npos) return kNaN;
  std::size_t colon = text.find(':', at);
  if (colon == std::string::npos) return kNaN;
  const char* start = text.c_str() + colon + 1;
  char* end = nullptr;
  const double value = std::strtod(start, &end);
  return end == start ? kNaN : value;
}

std::vector<double> level_metrics(const std::string& folder) {
  const std::string path = (fs::path(folder) / "metrics.json").string();
  std::ifstream in(path);
  if (!in) throw Error(located(path, "", "cannot read the level's metrics"));
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::vector<double> values;
  for (const auto& metric : converge_metrics()) {
    if (metric.key == "slip_circle") {
      // "slip_circle": {"xc_m": ..., "yc_m": ..., "r_m": ...} or null (no circle fitted).
      const std::size_t at = text.find("\"slip_circle\"");
      const std::size_t value = at == std::string::npos ? at : text.find_first_not_of(" :\n", at + 13);
      const bool object = value != std::string::npos && text[value] == '{';
      values.push_back(object ? json_number(text, "r_m", value) : kNaN);
    } else {
      values.push_back(json_number(text, metric.key));
    }
  }
  return values;
}

void read_run_attributes(Level& level) {
  const h5::File file = h5::File::open_read((fs::path(level.folder) / "results.h5").string());
  level.particles = h5::get_int(file, "/", "particles");
  level.steps = h5::get_int(file, "/", "steps");
  level.loop_seconds = h5::get_double(file, "/", "loop_seconds");
}

std::string level_name(int k, double size) {
  std::ostringstream name;
  name << "level" << k + 1 << "_h" << std::setprecision(6) << size;
  return name.str();
}

std::vector<std::string> with_size(const std::vector<std::string>& overrides, double size) {
  std::vector<std::string> all = overrides;
  all.push_back("mesh.size=" + number_text(size));
  return all;
}

// The finest level run with another transfer (--transfers).
struct TransferLevel {
  std::string name;
  std::vector<std::string> overrides;  // the transfer's --set, after the study's own
  bool reused = false;                 // the scene's own transfer: the finest level itself
  Level run;
};

struct Study {
  std::vector<Level> levels;  // coarse to fine
  double ratio = 2;
  std::vector<std::optional<GridConvergence>> convergence;  // per metric; none with 2 levels or a missing value
  std::vector<TransferLevel> transfers;                     // --transfers, at the finest size
};

// The transfers' lowest and highest value of metric m at the finest size; NaNs when any is missing.
struct TransferRange {
  double low = kNaN, high = kNaN, mean = kNaN;
  double spread() const { return high - low; }
  double spread_percent() const { return 100 * spread() / std::abs(mean); }
};

TransferRange transfer_range(const Study& study, std::size_t m) {
  TransferRange range;
  if (study.transfers.empty()) return range;
  double low = std::numeric_limits<double>::infinity(), high = -low, sum = 0;
  for (const auto& t : study.transfers) {
    if (!std::isfinite(t.run.values[m])) return range;
    low = std::min(low, t.run.values[m]);
    high = std::max(high, t.run.values[m]);
    sum += t.run.values[m];
  }
  return {low, high, sum / static_cast<double>(study.transfers.size())};
}

// Relative change between the two finest levels, |f1 - f2| / |f1|.
double finest_change(const Study& study, std::size_t m) {
  const auto& levels = study.levels;
  const double f1 = levels.back().values[m], f2 = levels[levels.size() - 2].values[m];
  return f1 != 0 ? std::abs(f1 - f2) / std::abs(f1) : kNaN;
}

std::string fixed(double value, int digits) {
  if (!std::isfinite(value)) return "-";
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

std::string csv_number(double value) { return std::isfinite(value) ? number_text(value, 10) : ""; }

void write_csv(const Study& study, const std::string& path) {
  std::ostringstream csv;
  csv << "metric,unit";
  for (const auto& level : study.levels) csv << ",h=" << number_text(level.size, 6);
  csv << ",convergence,order,observed_order,extrapolated,gci,gci_percent,safety_factor,finest_change_percent\n";
  const auto& metrics = converge_metrics();
  for (std::size_t m = 0; m < metrics.size(); ++m) {
    if (!std::isfinite(study.levels.back().values[m])) continue;
    csv << metrics[m].name << "," << metrics[m].unit;
    for (const auto& level : study.levels) csv << "," << csv_number(level.values[m]);
    const auto& g = study.convergence[m];
    if (g)
      csv << "," << convergence_name(g->kind) << "," << csv_number(g->order) << "," << csv_number(g->observed_order)
          << "," << csv_number(g->extrapolated) << "," << csv_number(g->band) << ","
          << csv_number(100 * g->relative_band) << "," << csv_number(g->safety_factor);
    else
      csv << ",,,,,,,";
    csv << "," << csv_number(100 * finest_change(study, m)) << "\n";
  }
  write_text_atomically(path, csv.str());
}

std::string markdown(const Study& study, const std::string& scene_path) {
  std::ostringstream md;
  md << "# Mesh convergence of " << scene_path << "\n\n";
  md << "| level | mesh.size (m) | particles | steps | time loop (s) | wall time here (s) |\n|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < study.levels.size(); ++k) {
    const Level& l = study.levels[k];
    md << "| " << k + 1 << " | " << number_text(l.size, 6) << " | " << l.particles << " | " << l.steps << " | "
       << fixed(l.loop_seconds, 1) << " | " << fixed(l.wall_seconds, 1) << " |\n";
  }
  md << "\n| metric |";
  for (const auto& l : study.levels) md << " h = " << number_text(l.size, 6) << " |";
  md << " change, two finest | convergence | order p | extrapolate | GCI band (fine) |\n|---|";
  for (std::size_t k = 0; k < study.levels.size(); ++k) md << "---|";
  md << "---|---|---|---|---|\n";
  const auto& metrics = converge_metrics();
  for (std::size_t m = 0; m < metrics.size(); ++m) {
    if (!std::isfinite(study.levels.back().values[m])) continue;
    md << "| " << metrics[m].name << " (" << metrics[m].unit << ") |";
    for (const auto& l : study.levels) md << " " << fixed(l.values[m], 3) << " |";
    md << " " << fixed(100 * finest_change(study, m), 1) << " % |";
    const auto& g = study.convergence[m];
    if (g)
      md << " " << convergence_name(g->kind) << (g->asymptotic ? "" : " (not in the asymptotic range)") << " | "
         << fixed(g->observed_order, 2) << (g->observed_order > g->order ? " (capped at 2)" : "") << " | "
         << fixed(g->extrapolated, 3) << " | " << fixed(study.levels.back().values[m], 3) << " ± " << fixed(g->band, 3)
         << " (" << fixed(100 * g->relative_band, 1) << " %, Fs = " << fixed(g->safety_factor, 2) << ") |\n";
    else
      md << " - | - | - | two levels: no band |\n";
  }
  if (!study.transfers.empty()) {
    md << "\n## The transfers at the finest size (mesh.size = " << number_text(study.levels.back().size, 6)
       << " m)\n\n| metric |";
    for (const auto& t : study.transfers) md << " " << t.name << " |";
    md << " spread (max - min) | spread / mean | mesh band (GCI) | all: lowest - band .. highest + band |\n|---|";
    for (std::size_t k = 0; k < study.transfers.size(); ++k) md << "---|";
    md << "---|---|---|---|\n";
    for (std::size_t m = 0; m < metrics.size(); ++m) {
      if (!std::isfinite(study.levels.back().values[m])) continue;
      md << "| " << metrics[m].name << " (" << metrics[m].unit << ") |";
      for (const auto& t : study.transfers) md << " " << fixed(t.run.values[m], 3) << " |";
      const TransferRange range = transfer_range(study, m);
      const auto& g = study.convergence[m];
      md << " " << fixed(range.spread(), 3) << " | " << fixed(range.spread_percent(), 1) << " % | "
         << (g ? fixed(g->band, 3) : std::string("-")) << " | ";
      if (g && std::isfinite(range.spread())) md << fixed(range.low - g->band, 3) << " .. " << fixed(range.high + g->band, 3);
      else md << "-";
      md << " |\n";
    }
    md << "\n| transfer | folder | steps | time loop (s) | wall time here (s) |\n|---|---|---|---|---|\n";
    for (const auto& t : study.transfers)
      md << "| " << t.name << " | " << (t.reused ? "the finest level (the scene's transfer)" : t.run.folder) << " | "
         << t.run.steps << " | " << fixed(t.run.loop_seconds, 1) << " | " << fixed(t.run.wall_seconds, 1) << " |\n";
    md << "\nThe band measures one scheme's mesh error; the spread, the scheme's: an error bar for the answer "
          "covers both (docs/converge.md, \"The transfers\").\n";
  }
  md << "\nRatio " << number_text(study.ratio, 6)
     << ". Order, extrapolate and band from the three finest levels by Celik et al. (2008) and Roache (1998): "
        "monotone convergence, Fs = 1.25 with the observed order (capped at 2); oscillatory or divergent, "
        "Fs = 3 with p = 1 and no extrapolate (docs/converge.md).\n";
  return md.str();
}

void print_table(const Study& study, std::ostream& log) {
  const auto& metrics = converge_metrics();
  log << "\n  " << std::left << std::setw(22) << "metric";
  for (const auto& l : study.levels) log << std::right << std::setw(10) << ("h=" + number_text(l.size, 4));
  log << std::setw(9) << "change" << "  band (fine)\n";
  for (std::size_t m = 0; m < metrics.size(); ++m) {
    if (!std::isfinite(study.levels.back().values[m])) continue;
    log << "  " << std::left << std::setw(22) << (metrics[m].name + " (" + metrics[m].unit + ")") << std::right;
    for (const auto& l : study.levels) log << std::setw(10) << fixed(l.values[m], 3);
    log << std::setw(7) << fixed(100 * finest_change(study, m), 1) << " %  ";
    const auto& g = study.convergence[m];
    if (g)
      log << fixed(study.levels.back().values[m], 3) << " ± " << fixed(g->band, 3) << " (" << convergence_name(g->kind)
          << (g->kind == Convergence::Monotone ? ", p = " + fixed(g->observed_order, 2) : std::string(", Fs = 3, p = 1"))
          << ")";
    else
      log << "-";
    log << "\n";
  }
  if (study.transfers.empty()) return;
  log << "\n  at h=" << number_text(study.levels.back().size, 4) << " " << std::left << std::setw(13) << "transfers";
  for (const auto& t : study.transfers) log << std::right << std::setw(10) << t.name;
  log << std::setw(10) << "spread" << "\n";
  for (std::size_t m = 0; m < metrics.size(); ++m) {
    if (!std::isfinite(study.levels.back().values[m])) continue;
    log << "  " << std::left << std::setw(22) << (metrics[m].name + " (" + metrics[m].unit + ")") << std::right;
    for (const auto& t : study.transfers) log << std::setw(10) << fixed(t.run.values[m], 3);
    const TransferRange range = transfer_range(study, m);
    log << std::setw(10) << fixed(range.spread(), 3) << " (" << fixed(range.spread_percent(), 1) << " %)\n";
  }
}

void write_transfers_csv(const Study& study, const std::string& path) {
  std::ostringstream csv;
  csv << "metric,unit";
  for (const auto& t : study.transfers) csv << "," << t.name;
  csv << ",spread,spread_percent_of_mean,gci\n";
  const auto& metrics = converge_metrics();
  for (std::size_t m = 0; m < metrics.size(); ++m) {
    if (!std::isfinite(study.levels.back().values[m])) continue;
    csv << metrics[m].name << "," << metrics[m].unit;
    for (const auto& t : study.transfers) csv << "," << csv_number(t.run.values[m]);
    const TransferRange range = transfer_range(study, m);
    csv << "," << csv_number(range.spread()) << "," << csv_number(range.spread_percent()) << ","
        << (study.convergence[m] ? csv_number(study.convergence[m]->band) : "") << "\n";
  }
  write_text_atomically(path, csv.str());
}

// Runs the pipeline for one level into level.folder and reads back its metrics; `what` names it
// in the message of a failed run.
void run_level(const ConvergeOptions& options, const std::vector<std::string>& overrides, Level& level,
               const std::string& what, std::ostream& log) {
  StageOptions stage;
  stage.overrides = overrides;
  stage.out = level.folder;
  stage.quiet = true;
  stage.threads = options.threads;
  const Clock::time_point start = Clock::now();
  std::ostringstream discarded;
  const int status = run_pipeline(options.scene_path, stage, discarded);
  level.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (status != 0) throw Error("converge: " + what + " failed: " + discarded.str());
  read_run_attributes(level);
  level.values = level_metrics(level.folder);
  if (!options.quiet)
    log << "  done in " << fixed(level.wall_seconds, 1) << " s (time loop " << fixed(level.loop_seconds, 1) << " s, "
        << level.particles << " particles, " << level.steps << " steps): runout " << fixed(level.values[0], 3) << " m"
        << std::endl;
}

// The run settings a transfer's overrides give at the finest level, to tell the scene's own.
bool same_transfer(const RunSettings& a, const RunSettings& b) {
  return a.transfer == b.transfer && (a.transfer != Transfer::Xpic || a.xpic_order == b.xpic_order) &&
         (a.transfer != Transfer::PicBlend || a.pic_fraction == b.pic_fraction);
}

bool is_transfer_key(const std::string& text) {
  for (const char* key : {"run.transfer=", "run.xpic_order=", "run.pic_fraction="})
    if (text.rfind(key, 0) == 0) return true;
  return false;
}

}  // namespace

constexpr const char* kNoConvergeMetrics =
    "converge follows runout, crest retreat, travel angle, failed area and the slip circle: the scene's metrics "
    "give none of them (add \"runout\" or \"failure_surface\")";

const std::vector<ConvergeMetric>& converge_metrics() {
  static const std::vector<ConvergeMetric> metrics{
      {"runout_distance_m", "runout", "m"},
      {"crest_retreat_m", "crest retreat", "m"},
      {"travel_angle_deg", "travel angle", "deg"},
      {"failed_area_m2", "failed area", "m^2"},
      {"slip_circle", "slip-circle radius", "m"},
  };
  return metrics;
}

int run_converge(const ConvergeOptions& options, std::ostream& log) {
  if (options.levels < kMinLevels || options.levels > kMaxLevels)
    throw Error("converge: --levels: expected an integer in [" + std::to_string(kMinLevels) + ", " +
                std::to_string(kMaxLevels) + "], got " + std::to_string(options.levels));
  if (!(options.ratio > 1) || !std::isfinite(options.ratio))
    throw Error("converge: --ratio: expected a number > 1, got " + number_text(options.ratio, 6));
  const Scene scene = load_scene(options.scene_path, options.overrides);
  // The metrics converge follows come from post's runout and failure surface: a scene that asks
  // for neither is refused before any level runs (before, after running every level).
  const auto& asked = scene.post.metrics;
  if (std::find(asked.begin(), asked.end(), "runout") == asked.end() &&
      std::find(asked.begin(), asked.end(), "failure_surface") == asked.end())
    throw Error(located(options.scene_path, "post.metrics", kNoConvergeMetrics));
  // --set mesh.size sets the coarsest level; each level then gives its own.
  std::vector<std::string> overrides;
  for (const auto& text : options.overrides)
    if (text.rfind("mesh.size=", 0) != 0) overrides.push_back(text);
  double h0 = scene.mesh.size.value_or(0);
  if (!scene.mesh.size) {
    const preproc::SizeEstimate estimate = preproc::estimate_size(scene);
    if (!estimate.known || !(estimate.element_size > 0))
      throw Error(located(options.scene_path, "mesh.size",
                          "converge needs the coarsest element size: the scene gives no mesh.size and the size of "
                          "its .geo cannot be read"));
    h0 = estimate.element_size;
  }

  Study study;
  study.ratio = options.ratio;
  // Every level is checked against memory before the first one runs.
  for (int k = 0; k < options.levels; ++k) {
    Level level;
    level.size = h0 / std::pow(options.ratio, k);
    try {
      preproc::check_size(load_scene(options.scene_path, with_size(overrides, level.size)));
    } catch (const Error& error) {
      throw Error("converge: level " + std::to_string(k + 1) + " (mesh.size = " + number_text(level.size, 6) +
                  " m) cannot run: " + error.what());
    }
    study.levels.push_back(level);
  }
  // Each transfer of --transfers is checked on the finest level's scene before anything runs (the
  // scene reader refuses, for example, APIC on linear triangles).
  const double finest = study.levels.back().size;
  const RunSettings own = load_scene(options.scene_path, with_size(overrides, finest)).run;
  std::vector<std::string> without_transfer;
  for (const auto& text : overrides)
    if (!is_transfer_key(text)) without_transfer.push_back(text);
  for (const auto& name : options.transfers) {
    for (const auto& t : study.transfers)
      if (t.name == name) throw Error("converge: --transfers: '" + name + "' is listed twice");
    TransferLevel t;
    t.name = name;
    t.overrides = with_size(without_transfer, finest);
    try {
      for (const auto& o : transfer_overrides(name)) t.overrides.push_back(o);
    } catch (const Error& error) {
      throw Error(std::string("converge: --transfers: ") + error.what());
    }
    try {
      t.reused = same_transfer(load_scene(options.scene_path, t.overrides).run, own);
    } catch (const Error& error) {
      throw Error("converge: --transfers " + name + " cannot run: " + error.what());
    }
    study.transfers.push_back(t);
  }

  const std::string folder =
      options.out ? output_folder(options.out, scene)
                  : output_folder((fs::path("out") / scene.name / "converge").string(), scene);
  const FolderLock lock(folder);  // one study per folder at a time; each level locks its own
  for (int k = 0; k < options.levels; ++k) {
    Level& level = study.levels[k];
    level.folder = (fs::path(folder) / level_name(k, level.size)).string();
    if (!options.quiet)
      log << "level " << k + 1 << "/" << options.levels << ": mesh.size = " << number_text(level.size, 6) << " m in "
          << level.folder << " ..." << std::endl;
    run_level(options, with_size(overrides, level.size), level, "level " + std::to_string(k + 1), log);
  }

  for (std::size_t k = 0; k < study.transfers.size(); ++k) {
    TransferLevel& t = study.transfers[k];
    if (t.reused) {
      t.run = study.levels.back();
      t.run.wall_seconds = 0;
      if (!options.quiet) log << "transfer " << t.name << ": the scene's own, the finest level" << std::endl;
      continue;
    }
    t.run.size = finest;
    t.run.folder = (fs::path(folder) / ("finest_" + t.name)).string();
    if (!options.quiet)
      log << "transfer " << k + 1 << "/" << study.transfers.size() << ": " << t.name << " at mesh.size = "
          << number_text(finest, 6) << " m in " << t.run.folder << " ..." << std::endl;
    run_level(options, t.overrides, t.run, "transfer " + t.name, log);
  }

  const auto& metrics = converge_metrics();
  bool any = false;
  for (std::size_t m = 0; m < metrics.size(); ++m) {
    const std::size_t n = study.levels.size();
    bool complete = true;
    for (const auto& l : study.levels) complete = complete && std::isfinite(l.values[m]);
    any = any || std::isfinite(study.levels.back().values[m]);
    if (n >= 3 && complete)
      study.convergence.emplace_back(grid_convergence(study.levels[n - 1].values[m], study.levels[n - 2].values[m],
                                                      study.levels[n - 3].values[m], options.ratio, options.ratio));
    else
      study.convergence.emplace_back(std::nullopt);
  }
  if (!any) throw Error(located(options.scene_path, "post.metrics", kNoConvergeMetrics));

  const std::string csv = (fs::path(folder) / "converge.csv").string();
  write_csv(study, csv);
  if (!study.transfers.empty()) write_transfers_csv(study, (fs::path(folder) / "transfers.csv").string());
  write_text_atomically((fs::path(folder) / "converge.md").string(), markdown(study, options.scene_path));
  if (!options.quiet) print_table(study, log);
  try {
    std::ostringstream figure_log;
    postproc::run_figure_script(postproc::figure_script("converge_figure.py"),
                                {csv, (fs::path(folder) / "converge.png").string()}, figure_log);
    if (!options.quiet) log << figure_log.str();
  } catch (const Error& error) {
    log << "talus: " << error.what() << "\n";
    return 1;
  }
  if (!options.quiet) log << "wrote " << csv << ", converge.md and converge.png in " << folder << "\n";
  return 0;
}

}  // namespace talus::workflow
