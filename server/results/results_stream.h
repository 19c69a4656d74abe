// A results directory written as the run goes (`mbstream simulate`): each frame's rows are
// appended to joints.csv.tmp, ... as it comes, so a run's memory does not grow with its
// length; Finish renames the files into place and writes stats.json. The files are
// byte-identical to WriteResultsDirectory's for the same run (results_csv.h).
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "server/results/results_csv.h"
#include "server/results/results_files.h"
#include "server/sim/run_result.h"

namespace mbstream {

class ResultsStreamWriter : public FrameSink {
 public:
  // Creates `directory` if missing; throws InputError naming it when it cannot.
  explicit ResultsStreamWriter(const std::string& directory);

  void OnFrame(const RunResult& result, int frame) override;
  bool KeepsFrames() const override { return true; }

  // Frames written so far.
  long frames() const { return frames_; }

  // Closes the files, renames them into place (removing optional files this result does not
  // have), and writes stats.json with the count of frames written. Throws InputError naming
  // a file that could not be written (a full disk).
  void Finish(const RunResult& result, const RunProvenance& provenance);

 private:
  struct OpenSeries {
    results_csv::Series series;
    std::ofstream out;
  };
  void Open(const RunResult& result);
  void Check(const OpenSeries& open) const;

  std::filesystem::path directory_;
  std::vector<std::unique_ptr<OpenSeries>> files_;
  std::ofstream contacts_;  // contacts.csv.tmp, once a frame of a run with contact came
  std::vector<double> row_;
  std::string text_;
  long frames_ = 0;
  bool opened_ = false;
};

}  // namespace mbstream
