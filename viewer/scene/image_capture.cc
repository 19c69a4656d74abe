#include "viewer/scene/image_capture.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <cstring>
#include <fstream>

#include "viewer/scene/scene_error.h"

namespace mbstream::viewer {

namespace {

vtkSmartPointer<vtkWindowToImageFilter> Grab(vtkRenderWindow* window) {
  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();  // the caller has just rendered
  grab->Update();
  return grab;
}

}  // namespace

RgbImage CaptureWindow(vtkRenderWindow* window) {
  vtkSmartPointer<vtkWindowToImageFilter> grab = Grab(window);
  vtkImageData* image = grab->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  RgbImage out;
  out.width = dims[0];
  out.height = dims[1];
  out.rgb.resize(size_t(out.width) * out.height * 3);
  const auto* data = static_cast<const std::uint8_t*>(image->GetScalarPointer());
  const size_t row = size_t(out.width) * 3;
  for (int y = 0; y < out.height; ++y) {  // VTK's rows start at the bottom
    std::memcpy(&out.rgb[size_t(y) * row], data + size_t(out.height - 1 - y) * row, row);
  }
  return out;
}

void WritePng(vtkRenderWindow* window, const std::filesystem::path& path) {
  const std::string bytes = PngBytes(window);
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    throw SceneError(path.string() + ": cannot write the PNG file; check the directory " +
                     "exists and is writable");
  }
}

std::string PngBytes(vtkRenderWindow* window) {
  vtkSmartPointer<vtkWindowToImageFilter> grab = Grab(window);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  writer->WriteToMemoryOn();
  writer->Write();
  vtkUnsignedCharArray* result = writer->GetResult();
  return std::string(reinterpret_cast<const char*>(result->GetPointer(0)),
                     static_cast<size_t>(result->GetNumberOfTuples()));
}

}  // namespace mbstream::viewer
