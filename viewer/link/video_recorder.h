// Records what a render window shows into an Ogg Theora video (VTK's writer).
#pragma once

#include <vtkNew.h>
#include <vtkOggTheoraWriter.h>
#include <vtkRenderWindow.h>
#include <vtkWindowToImageFilter.h>

#include <string>

namespace mbstream::viewer {

class VideoRecorder {
 public:
  // `path` ends in .ogv; `fps` is the video's frame rate.
  VideoRecorder(std::string path, int fps);
  ~VideoRecorder();  // End()

  // Adds the window's current image as the next video frame (the first call starts the
  // file; later windows must have the same size).
  void AddFrame(vtkRenderWindow* window);
  void End();
  int frames() const { return frames_; }

 private:
  std::string path_;
  int fps_;
  vtkNew<vtkWindowToImageFilter> capture_;
  vtkNew<vtkOggTheoraWriter> writer_;
  bool started_ = false;
  int frames_ = 0;
};

}  // namespace mbstream::viewer
