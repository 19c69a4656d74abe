#include "viewer/link/video_recorder.h"

#include <spdlog/spdlog.h>

namespace mbstream::viewer {

VideoRecorder::VideoRecorder(std::string path, int fps) : path_(std::move(path)), fps_(fps) {}

VideoRecorder::~VideoRecorder() { End(); }

void VideoRecorder::AddFrame(vtkRenderWindow* window) {
  capture_->SetInput(window);
  capture_->SetInputBufferTypeToRGB();
  capture_->ReadFrontBufferOff();
  capture_->Modified();
  if (!started_) {
    writer_->SetInputConnection(capture_->GetOutputPort());
    writer_->SetFileName(path_.c_str());
    writer_->SetRate(fps_);
    writer_->SetQuality(2);
    writer_->Start();
    started_ = true;
  }
  writer_->Write();
  ++frames_;
}

void VideoRecorder::End() {
  if (!started_) return;
  writer_->End();
  started_ = false;
  spdlog::info("video {} written: {} frames at {} fps", path_, frames_, fps_);
}

}  // namespace mbstream::viewer
