#include "unstructured_writer.hpp"

#include <sage/output/output_file.hpp>
#include <sage/output/vtk_writer.hpp>

#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

namespace sage::output {

void write_unstructured(const std::string& path, vtkUnstructuredGrid* grid) {
  write_atomically(path, [&](const std::string& temporary) {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToLZ4();
    if (writer->Write() != 1 || writer->GetErrorCode() != 0)
      throw OutputError(path + ": VTK could not write the file (disk full or no permission?)");
  });
}

void add_arrays(vtkUnstructuredGrid* grid, const std::vector<PointArray>& arrays, const std::vector<vtkIdType>& used) {
  const vtkIdType count = used.empty() ? grid->GetNumberOfPoints() : static_cast<vtkIdType>(used.size());
  for (const PointArray& a : arrays) {
    vtkNew<vtkDoubleArray> data;
    data->SetName(a.name.c_str());
    data->SetNumberOfComponents(a.components);
    data->SetNumberOfTuples(count);
    for (vtkIdType i = 0; i < count; ++i) {
      const auto from = static_cast<std::size_t>(used.empty() ? i : used[static_cast<std::size_t>(i)]);
      for (int c = 0; c < a.components; ++c)
        data->SetComponent(i, c, a.values[from * static_cast<std::size_t>(a.components) + static_cast<std::size_t>(c)]);
    }
    grid->GetPointData()->AddArray(data);
  }
  if (!arrays.empty()) grid->GetPointData()->SetActiveScalars(arrays.front().name.c_str());
}

}  // namespace sage::output
