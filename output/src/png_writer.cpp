#include <sage/output/output_file.hpp>
#include <sage/output/png_writer.hpp>
#include <sage/output/vtk_writer.hpp>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <cstring>

namespace sage::output {

void write_png(const std::string& path, const RgbImage& image) {
  if (image.width <= 0 || image.height <= 0) throw OutputError(path + ": cannot write an empty image");
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* out = static_cast<std::uint8_t*>(data->GetScalarPointer());
  const std::size_t row = 3 * static_cast<std::size_t>(image.width);
  for (int y = 0; y < image.height; ++y)
    std::memcpy(out + row * (image.height - 1 - y), image.rgb.data() + row * y, row);
  // VTK reports write errors through its error macros only: write_atomically
  // checks the folder first, so that the user gets a message and an exit code.
  write_atomically(path, [&](const std::string& temporary) {
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(data);
    writer->Write();
    if (writer->GetErrorCode() != 0) throw OutputError(path + ": VTK could not write the PNG file");
  });
}

}  // namespace sage::output
