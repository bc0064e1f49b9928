#pragma once
// Running the `sage` program from tests: exit code and all output, scratch
// files in the test process's own temporary folder, numbers of the printed
// summary, and the VTK files it writes read back.

#include <sys/wait.h>

#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <test_files.hpp>

namespace sage_cli_test {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

inline Result run(const std::string& args) {
  const std::string command = std::string(SAGE_EXECUTABLE) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string output;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe)) output += buffer.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

inline fs::path scratch(const std::string& name) { return sage::test::scratch_dir() / name; }

inline std::string write_file(const std::string& name, const std::string& text) {
  const fs::path p = scratch(name);
  std::ofstream(p) << text;
  return p.string();
}

/// The number printed right after `label` in `output` (NaN when `label` is missing).
inline double number_after(const std::string& output, const std::string& label) {
  const auto at = output.find(label);
  if (at == std::string::npos) return std::nan("");
  try {
    return std::stod(output.substr(at + label.size()));
  } catch (const std::exception&) {
    return std::nan("");
  }
}

/// A .vtu file as VTK reads it back.
inline vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& path) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

/// A .vti file as VTK reads it back.
inline vtkSmartPointer<vtkImageData> read_vti(const fs::path& path) {
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

/// The values of a one-component point array (empty when it is missing).
inline std::vector<double> point_values(vtkDataSet* data, const char* name) {
  std::vector<double> values;
  vtkDataArray* array = data ? data->GetPointData()->GetArray(name) : nullptr;
  for (vtkIdType i = 0; array && i < array->GetNumberOfTuples(); ++i) values.push_back(array->GetComponent(i, 0));
  return values;
}

/// The box [lo, hi] as 12 outward-oriented triangles (OFF), written to
/// the scratch folder as `name`.
inline std::string write_box_off(const std::string& name, const std::array<double, 3>& lo,
                                 const std::array<double, 3>& hi) {
  std::string text = "OFF\n8 12 0\n";
  for (int v = 0; v < 8; ++v) {  // corners 0-3 at z = lo, 4-7 at z = hi, anticlockwise from (lo, lo)
    const int xy = v % 4;
    const double x = (xy == 1 || xy == 2) ? hi[0] : lo[0], y = xy >= 2 ? hi[1] : lo[1], z = v >= 4 ? hi[2] : lo[2];
    text += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
  }
  text +=
      "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 2 3 7\n3 2 7 6\n3 1 2 6\n3 1 6 5\n3 3 0 4\n3 3 4 "
      "7\n";
  return write_file(name, text);
}

/// The cube [lo, hi]^3 (write_box_off).
inline std::string write_cube_off(const std::string& name, double lo, double hi) {
  return write_box_off(name, {lo, lo, lo}, {hi, hi, hi});
}

}  // namespace sage_cli_test
