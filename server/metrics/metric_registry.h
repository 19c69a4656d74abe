// A small metrics registry for operators: counters, gauges and histograms in label families,
// rendered in the Prometheus text format (text_format.h) when scraped.
//
// Families and their labelled children are created at start-up (Registry::Counter,
// Family::With); afterwards a hot path only adds to atomics: Counter::Add, Gauge::Set and
// Histogram::Observe take no lock and allocate nothing. Children live as long as the registry
// and never move, so callers keep references to them. The registry is passed to what it
// measures; it is never global, and the engine (server/sim and below) knows nothing of it.
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "server/metrics/text_format.h"

namespace mbstream::metrics {

class Counter {
 public:
  void Add(double amount = 1.0) { value_.fetch_add(amount, std::memory_order_relaxed); }
  double value() const { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<double> value_{0.0};
};

class Gauge {
 public:
  void Set(double value) { value_.store(value, std::memory_order_relaxed); }
  void Add(double amount) { value_.fetch_add(amount, std::memory_order_relaxed); }
  double value() const { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<double> value_{0.0};
};

// Counts observations into buckets with upper bounds `bounds` (ascending; +Inf is implied),
// with their sum and count. A non-finite value is not counted (nothing non-finite leaves the
// server).
class Histogram {
 public:
  explicit Histogram(std::vector<double> bounds);
  void Observe(double value);

  const std::vector<double>& bounds() const { return bounds_; }
  // Observations <= bounds()[i] (cumulative, as exposed); i == bounds().size() is +Inf.
  uint64_t CumulativeCount(size_t i) const;
  uint64_t count() const { return count_.load(std::memory_order_relaxed); }
  double sum() const { return sum_.load(std::memory_order_relaxed); }

 private:
  std::vector<double> bounds_;
  std::unique_ptr<std::atomic<uint64_t>[]> buckets_;  // per bucket, not cumulative
  std::atomic<uint64_t> count_{0};
  std::atomic<double> sum_{0.0};
};

// Bucket bounds start, start*factor, ... (count of them), as Prometheus' ExponentialBuckets.
std::vector<double> ExponentialBuckets(double start, double factor, int count);

// One metric name with its children, one per set of label values.
template <typename Metric>
class Family {
 public:
  Family(std::vector<std::string> label_names, std::function<std::unique_ptr<Metric>()> make)
      : label_names_(std::move(label_names)), make_(std::move(make)) {}

  // The child with these label values (as many as the family's label names), created on first
  // use. Call at start-up and keep the reference; it takes a lock.
  Metric& With(const std::vector<std::string>& values);

  template <typename Visit>  // Visit(const Labels&, const Metric&)
  void ForEach(Visit visit) const {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Child& child : children_) visit(child.labels, *child.metric);
  }

 private:
  struct Child {
    std::vector<std::string> values;
    Labels labels;
    std::unique_ptr<Metric> metric;
  };
  std::vector<std::string> label_names_;
  std::function<std::unique_ptr<Metric>()> make_;
  mutable std::mutex mutex_;
  std::deque<Child> children_;
};

class Registry {
 public:
  Registry();
  ~Registry();
  Registry(const Registry&) = delete;
  Registry& operator=(const Registry&) = delete;

  // New families. Names must be valid and unused (checked: a programming error throws).
  // Counters' names end in "_total" by convention; units go in the name (_seconds, _bytes).
  Family<Counter>& Counters(const std::string& name, const std::string& help,
                            std::vector<std::string> label_names = {});
  Family<Gauge>& Gauges(const std::string& name, const std::string& help,
                        std::vector<std::string> label_names = {});
  Family<Histogram>& Histograms(const std::string& name, const std::string& help,
                                std::vector<double> bounds,
                                std::vector<std::string> label_names = {});
  // An unlabelled gauge read at scrape time (`read` runs on the scraping thread).
  void GaugeFunction(const std::string& name, const std::string& help,
                     std::function<double()> read);

  // The text exposition of every family, in the order they were added.
  std::string Exposition() const;

 private:
  struct Entry;
  Entry& Add(const std::string& name, const std::string& help,
             const std::vector<std::string>& label_names);
  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<Entry>> entries_;
};

template <typename Metric>
Metric& Family<Metric>::With(const std::vector<std::string>& values) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Child& child : children_) {
    if (child.values == values) return *child.metric;
  }
  if (values.size() != label_names_.size()) {
    throw std::invalid_argument("metric family: " + std::to_string(values.size()) +
                                " label values for " + std::to_string(label_names_.size()) +
                                " label names");
  }
  Child child{values, {}, make_()};
  for (size_t i = 0; i < values.size(); ++i) child.labels.emplace_back(label_names_[i], values[i]);
  children_.push_back(std::move(child));
  return *children_.back().metric;
}

}  // namespace mbstream::metrics
