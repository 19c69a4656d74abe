#include "server/results/results_stream.h"

#include <system_error>

#include "shared/common/check.h"

namespace mbstream {

namespace fs = std::filesystem;

ResultsStreamWriter::ResultsStreamWriter(const std::string& directory) : directory_(directory) {
  std::error_code error;
  fs::create_directories(directory_, error);
  if (error) {
    throw InputError("cannot create results directory " + directory + ": " + error.message());
  }
}

void ResultsStreamWriter::Open(const RunResult& result) {
  opened_ = true;
  for (results_csv::Series& series : results_csv::SeriesOf(result)) {
    auto open = std::make_unique<OpenSeries>();
    const fs::path temporary = directory_ / (series.file + ".tmp");
    open->out.open(temporary, std::ios::binary | std::ios::trunc);
    if (!open->out) {
      throw InputError("cannot write " + temporary.string() +
                       ": check that the directory is writable");
    }
    open->out << series.header << '\n';
    row_.resize(std::max<size_t>(row_.size(), series.width));
    open->series = std::move(series);
    files_.push_back(std::move(open));
  }
}

void ResultsStreamWriter::Check(const OpenSeries& open) const {
  if (!open.out) {
    throw InputError("writing " + (directory_ / (open.series.file + ".tmp")).string() +
                     " failed: is the disk full?");
  }
}

void ResultsStreamWriter::OnFrame(const RunResult& result, int frame) {
  if (!opened_) Open(result);
  for (const auto& open : files_) {
    open->series.values(result, frame, row_.data());
    text_.clear();
    results_csv::AppendRow(text_, result.t[frame], row_.data(), open->series.width);
    open->out << text_;
    Check(*open);
  }
  if (result.contacts.active) {  // the latest frame's contacts (ContactLog::keep_records off)
    const fs::path temporary = directory_ / "contacts.csv.tmp";
    if (!contacts_.is_open()) {
      contacts_.open(temporary, std::ios::binary | std::ios::trunc);
      contacts_ << results_csv::kContactsHeader << '\n';
    }
    text_.clear();
    results_csv::AppendContactRows(text_, result.contacts);
    contacts_ << text_;
    if (!contacts_)
      throw InputError("writing " + temporary.string() + " failed: is the disk full?");
  }
  ++frames_;
}

void ResultsStreamWriter::Finish(const RunResult& result, const RunProvenance& provenance) {
  if (!opened_) Open(result);  // no frame at all: header-only files
  std::error_code error;
  for (const char* optional : results_csv::kOptionalFiles) fs::remove(directory_ / optional, error);
  for (const auto& open : files_) {
    open->out.flush();
    Check(*open);
    open->out.close();
    results_csv::CommitFile(directory_ / open->series.file);
  }
  if (contacts_.is_open()) {
    contacts_.close();
    results_csv::CommitFile(directory_ / "contacts.csv");
  }
  results_csv::WriteFile(directory_ / "stats.json",
                         [&](std::ostream& out) { out << StatsJson(result, provenance, frames_); });
}

}  // namespace mbstream
