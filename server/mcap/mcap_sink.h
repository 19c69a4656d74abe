// Where an MCAP file's bytes go, in order: a file on disk (McapFileSink: written under a
// temporary name and renamed when complete) or a stream (the server's ExportMcap sends them
// to the client as they come). McapWriter writes every byte once, front to back, never
// seeking, so either holds no more than the writer hands it.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace mbstream::mcap {

class McapSink {
 public:
  virtual ~McapSink() = default;
  // The next bytes of the file. Throws when they cannot be written (the message names the
  // destination and what to do).
  virtual void Write(std::string_view bytes) = 0;
  // Every byte has been written: the file is complete. Throws as Write.
  virtual void Close() = 0;
};

// A file at `path`, written as `path`.tmp and renamed by Close; destroyed without Close, the
// temporary file is removed (a failed export leaves no half-written file).
class McapFileSink : public McapSink {
 public:
  // Throws InputError naming the file when it cannot be created.
  explicit McapFileSink(std::string path);
  ~McapFileSink() override;
  McapFileSink(const McapFileSink&) = delete;
  McapFileSink& operator=(const McapFileSink&) = delete;

  void Write(std::string_view bytes) override;
  void Close() override;

 private:
  std::string path_;
  std::string temporary_path_;
  std::FILE* file_ = nullptr;
  bool closed_ = false;
};

}  // namespace mbstream::mcap
