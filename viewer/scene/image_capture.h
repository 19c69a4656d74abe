// Reading a render window back: RGB pixels, PNG files and PNG bytes.
#pragma once

#include <filesystem>
#include <string>

#include <vtkRenderWindow.h>

#include "viewer/scene/rgb_image.h"

namespace mbstream::viewer {

RgbImage CaptureWindow(vtkRenderWindow* window);
// Throws SceneError naming the file when it cannot be written.
void WritePng(vtkRenderWindow* window, const std::filesystem::path& path);
std::string PngBytes(vtkRenderWindow* window);

}  // namespace mbstream::viewer
