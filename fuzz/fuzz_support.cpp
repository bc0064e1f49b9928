// What the fuzz targets share: the scratch folder, the GDAL sandbox, the
// problem files' domain check and the evaluation of a field.
#include "fuzz_targets.hpp"

#include <sage/scalars/interval.hpp>
#include <sage/tape/evaluator.hpp>
#include <sage/tape/tape.hpp>

#include <cpl_conv.h>
#include <cpl_http.h>
#include <gdal_priv.h>
#include <omp.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <set>

namespace sage::fuzz {

namespace {

/// Made on first use with copies of examples/models; removed at exit.
class Scratch {
 public:
  Scratch() : root_(std::filesystem::temp_directory_path() / ("sage-fuzz-" + std::to_string(getpid()))) {
    std::filesystem::remove_all(root_);
    std::filesystem::create_directories(root_ / "problems");
    std::filesystem::create_directories(root_ / "models");
    const std::filesystem::path models = std::filesystem::path(SAGE_SOURCE_DIR) / "examples" / "models";
    std::error_code ignored;
    for (const auto& entry : std::filesystem::directory_iterator(models, ignored))
      std::filesystem::copy_file(entry.path(), root_ / "models" / entry.path().filename(), ignored);
  }
  ~Scratch() {
    std::error_code ignored;
    std::filesystem::remove_all(root_, ignored);
  }
  const std::filesystem::path& root() const { return root_; }

 private:
  std::filesystem::path root_;
};

/// Answers every HTTP request GDAL makes (a GeoJSON "crs" of type "link"
/// fetches its URL) with an error, without touching the network.
CPLHTTPResult* refuse_http(const char*, CSLConstList, GDALProgressFunc, void*, CPLHTTPFetchWriteFunc, void*, void*) {
  auto* result = static_cast<CPLHTTPResult*>(CPLCalloc(1, sizeof(CPLHTTPResult)));
  result->nStatus = 1;
  result->pszErrBuf = CPLStrdup("HTTP is off in the fuzz targets");
  return result;
}

}  // namespace

const std::filesystem::path& scratch() {
  static const Scratch folder;
  return folder.root();
}

std::string write_scratch(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = (scratch() / name).string();
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) std::abort();
  if (size && std::fwrite(data, 1, size, file) != size) std::abort();
  std::fclose(file);
  return path;
}

void setup() {
  static std::once_flag once;
  std::call_once(once, [] {
    omp_set_num_threads(1);
    setenv("PROJ_NETWORK", "OFF", 1);
    CPLHTTPSetFetchCallback(refuse_http, nullptr);
    // Only the JSON vector drivers: other drivers would open other files
    // (a VRT names any path or URL) whatever the file's extension. GDAL_SKIP
    // also holds when sage calls GDALAllRegister itself.
    GDALAllRegister();
    const std::set<std::string> kept{"GeoJSON", "GeoJSONSeq", "ESRIJSON", "TopoJSON"};
    GDALDriverManager* drivers = GetGDALDriverManager();
    std::string skip;
    for (int i = 0; i < drivers->GetDriverCount(); ++i) {
      const std::string name = drivers->GetDriver(i)->GetDescription();
      if (!kept.count(name)) skip += (skip.empty() ? "" : ",") + name;
    }
    CPLSetConfigOption("GDAL_SKIP", skip.c_str());
    drivers->AutoSkipDrivers();
    (void)scratch();
  });
}

bool domain_stays_in_scratch(const std::string& text) {
  const nlohmann::json top = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!top.is_object()) return true;
  const auto domain = top.find("domain");
  if (domain == top.end() || !domain->is_string()) return true;
  // read_problem_file resolves a relative domain against the problem file's folder.
  const std::filesystem::path path = (scratch() / "problems" / domain->get<std::string>()).lexically_normal();
  const std::filesystem::path inside = path.lexically_relative(scratch());
  return !inside.empty() && *inside.begin() != "..";
}

bool skip_known_bugs() {
  static const bool skip = std::getenv("SAGE_FUZZ_KNOWN_BUGS") == nullptr;
  return skip;
}

void rejected(const std::exception& error) {
  static const bool verbose = std::getenv("SAGE_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "rejected: %s\n", error.what());
}

void evaluate(const Expr& field, int dimension) {
  const Tape tape(field, dimension);
  Evaluator<double> values(tape);
  const std::array<std::array<double, 3>, 4> points{
      {{0.0, 0.0, 0.0}, {0.3, -0.7, 0.1}, {1.5, 2.5, -0.5}, {-40.0, 1e3, 7.0}}};
  for (const auto& p : points) values.evaluate(p.data());
  Evaluator<Interval> boxes(tape);
  const std::array<Interval, 3> box{Interval(-1.0, 1.0), Interval(-0.5, 2.0), Interval(0.25, 0.75)};
  boxes.evaluate_with(box.data());
}

}  // namespace sage::fuzz
