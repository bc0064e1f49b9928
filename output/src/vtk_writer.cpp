#include <sage/output/output_file.hpp>
#include <sage/output/vtk_writer.hpp>

#include "provenance.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cstring>

namespace sage::output {

namespace {

vtkNew<vtkDoubleArray> make_array(const std::string& name, int components, const std::vector<double>& values) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(static_cast<vtkIdType>(values.size() / static_cast<std::size_t>(components)));
  std::copy(values.begin(), values.end(), a->GetPointer(0));
  return a;
}

/// Field data saying how the samples were made (ParaView shows it in the
/// spreadsheet view's field data): "evaluation" in words,
/// "far_field_tolerance" in field units (0 when exact) and, with far mesh
/// faces in single precision, "far_faces_deviation" as measured (relative
/// to the grid box's diagonal).
void add_provenance(vtkFieldData* data, const FieldSamples& s) {
  vtkNew<vtkStringArray> evaluation;
  evaluation->SetName("evaluation");
  evaluation->InsertNextValue(evaluation_text(s));
  data->AddArray(evaluation);
  if (s.far_faces) {
    vtkNew<vtkDoubleArray> deviation;
    deviation->SetName("far_faces_deviation");
    deviation->InsertNextValue(s.far_faces_deviation);
    data->AddArray(deviation);
  }
  vtkNew<vtkDoubleArray> tolerance;
  tolerance->SetName("far_field_tolerance");
  tolerance->InsertNextValue(s.far_field_tolerance);
  data->AddArray(tolerance);
}

void add_arrays(vtkPointData* data, const FieldSamples& s) {
  data->AddArray(make_array("omega", 1, s.omega));
  data->SetActiveScalars("omega");
  if (s.gradient.empty()) return;  // order 0: values only
  auto grad = make_array("grad_omega", 3, s.gradient);
  grad->SetComponentName(0, "x");
  grad->SetComponentName(1, "y");
  grad->SetComponentName(2, "z");
  data->AddArray(grad);
  data->AddArray(make_array("grad_norm", 1, s.gradient_norm));
  for (const DerivativeArray& d : s.higher) {
    auto a = make_array("d" + std::to_string(d.order) + "_omega", static_cast<int>(d.components.size()), d.values);
    for (std::size_t c = 0; c < d.components.size(); ++c)
      a->SetComponentName(static_cast<vtkIdType>(c), d.components[c].c_str());
    data->AddArray(a);
  }
  data->SetActiveVectors("grad_omega");
}

vtkNew<vtkUnstructuredGrid> unstructured(const FieldSamples& s) {
  const Grid& g = s.grid;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(g.size()));
  for (std::size_t i = 0; i < g.size(); ++i) points->SetPoint(static_cast<vtkIdType>(i), g.point(i).data());

  const vtkIdType nx = g.points[0], ny = g.points[1], nz = g.points[2];
  auto id = [&](vtkIdType i, vtkIdType j, vtkIdType k) { return i + nx * (j + ny * k); };
  vtkNew<vtkCellArray> cells;
  if (g.dimension == 2) {
    for (vtkIdType j = 0; j + 1 < ny; ++j)
      for (vtkIdType i = 0; i + 1 < nx; ++i) {
        const vtkIdType quad[4] = {id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0)};
        cells->InsertNextCell(4, quad);
      }
  } else {
    for (vtkIdType k = 0; k + 1 < nz; ++k)
      for (vtkIdType j = 0; j + 1 < ny; ++j)
        for (vtkIdType i = 0; i + 1 < nx; ++i) {
          const vtkIdType hex[8] = {id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
                                    id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
          cells->InsertNextCell(8, hex);
        }
  }
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->SetCells(g.dimension == 2 ? VTK_QUAD : VTK_HEXAHEDRON, cells);
  add_arrays(grid->GetPointData(), s);
  add_provenance(grid->GetFieldData(), s);
  return grid;
}

vtkNew<vtkImageData> image(const FieldSamples& s) {
  const Grid& g = s.grid;
  vtkNew<vtkImageData> img;
  img->SetDimensions(g.points[0], g.points[1], g.points[2]);
  img->SetOrigin(g.lo[0], g.lo[1], g.dimension == 3 ? g.lo[2] : 0.0);
  img->SetSpacing(g.spacing(0), g.spacing(1), g.dimension == 3 ? g.spacing(2) : 1.0);
  add_arrays(img->GetPointData(), s);
  add_provenance(img->GetFieldData(), s);
  return img;
}

template <class Writer, class Data>
void write_with(const std::string& path, Data* data) {
  write_atomically(path, [&](const std::string& temporary) {
    vtkNew<Writer> writer;
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(data);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToLZ4();  // zlib is 20x slower here for little gain on doubles
    if (writer->Write() != 1 || writer->GetErrorCode() != 0)
      throw OutputError(path + ": VTK could not write the file (disk full or no permission?)");
  });
}

}  // namespace

bool is_supported_field_path(const std::string& path) { return path.ends_with(".vtu") || path.ends_with(".vti"); }

void write_field(const std::string& path, const FieldSamples& samples) {
  if (!is_supported_field_path(path)) throw OutputError(path + ": unsupported extension (use .vtu or .vti)");
  if (path.ends_with(".vti")) {
    auto data = image(samples);
    write_with<vtkXMLImageDataWriter>(path, data.GetPointer());
  } else {
    auto data = unstructured(samples);
    write_with<vtkXMLUnstructuredGridWriter>(path, data.GetPointer());
  }
}

void write_surface(const std::string& path, const TriangleSurface& surface,
                   const std::vector<std::pair<std::string, std::vector<int>>>& cell_arrays) {
  if (!path.ends_with(".vtp")) throw OutputError(path + ": unsupported extension for a surface (use .vtp)");
  vtkNew<vtkPolyData> data;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(surface.points.size()));
  for (std::size_t i = 0; i < surface.points.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), surface.points[i].data());
  data->SetPoints(points);
  vtkNew<vtkCellArray> triangles;
  for (const auto& t : surface.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    triangles->InsertNextCell(3, ids);
  }
  data->SetPolys(triangles);
  for (const auto& [name, values] : cell_arrays) {
    if (values.size() != surface.triangles.size())
      throw std::invalid_argument("write_surface: array " + name + " needs one value per triangle");
    vtkNew<vtkIntArray> array;
    array->SetName(name.c_str());
    array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
    for (std::size_t i = 0; i < values.size(); ++i) array->SetValue(static_cast<vtkIdType>(i), values[i]);
    data->GetCellData()->AddArray(array);
  }
  write_with<vtkXMLPolyDataWriter>(path, data.Get());
}

}  // namespace sage::output
