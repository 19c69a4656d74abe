#include "server/metrics/metric_registry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <variant>

namespace mbstream::metrics {

Histogram::Histogram(std::vector<double> bounds)
    : bounds_(std::move(bounds)),
      buckets_(std::make_unique<std::atomic<uint64_t>[]>(bounds_.size() + 1)) {
  if (!std::is_sorted(bounds_.begin(), bounds_.end()) ||
      std::adjacent_find(bounds_.begin(), bounds_.end()) != bounds_.end()) {
    throw std::invalid_argument("histogram bucket bounds must increase strictly");
  }
}

void Histogram::Observe(double value) {
  if (!std::isfinite(value)) return;
  const size_t bucket =
      std::lower_bound(bounds_.begin(), bounds_.end(), value) - bounds_.begin();  // value <= le
  buckets_[bucket].fetch_add(1, std::memory_order_relaxed);
  sum_.fetch_add(value, std::memory_order_relaxed);
  count_.fetch_add(1, std::memory_order_relaxed);
}

uint64_t Histogram::CumulativeCount(size_t i) const {
  uint64_t total = 0;
  for (size_t b = 0; b <= std::min(i, bounds_.size()); ++b) {
    total += buckets_[b].load(std::memory_order_relaxed);
  }
  return total;
}

std::vector<double> ExponentialBuckets(double start, double factor, int count) {
  std::vector<double> bounds;
  double bound = start;
  for (int i = 0; i < count; ++i, bound *= factor) bounds.push_back(bound);
  return bounds;
}

struct Registry::Entry {
  std::string name;
  std::string help;
  std::variant<std::unique_ptr<Family<Counter>>, std::unique_ptr<Family<Gauge>>,
               std::unique_ptr<Family<Histogram>>, std::function<double()>>
      metrics;
};

Registry::Registry() = default;
Registry::~Registry() = default;

Registry::Entry& Registry::Add(const std::string& name, const std::string& help,
                               const std::vector<std::string>& label_names) {
  if (!IsMetricName(name)) throw std::invalid_argument("invalid metric name '" + name + "'");
  for (const std::string& label : label_names) {
    if (!IsLabelName(label) || label == "le") {
      throw std::invalid_argument("invalid label name '" + label + "' of metric " + name);
    }
  }
  std::lock_guard<std::mutex> lock(mutex_);
  for (const std::unique_ptr<Entry>& entry : entries_) {
    if (entry->name == name) throw std::invalid_argument("metric " + name + " added twice");
  }
  entries_.push_back(std::make_unique<Entry>());
  entries_.back()->name = name;
  entries_.back()->help = help;
  return *entries_.back();
}

namespace {

// A new family of `Metric`s in `entry`, each child made by `make`.
template <typename Metric, typename Entry, typename Make>
Family<Metric>& NewFamily(Entry& entry, std::vector<std::string> label_names, Make make) {
  auto family = std::make_unique<Family<Metric>>(std::move(label_names), std::move(make));
  Family<Metric>& result = *family;
  entry.metrics = std::move(family);
  return result;
}

}  // namespace

Family<Counter>& Registry::Counters(const std::string& name, const std::string& help,
                                    std::vector<std::string> label_names) {
  Entry& entry = Add(name, help, label_names);  // before label_names moves
  return NewFamily<Counter>(entry, std::move(label_names),
                            [] { return std::make_unique<Counter>(); });
}

Family<Gauge>& Registry::Gauges(const std::string& name, const std::string& help,
                                std::vector<std::string> label_names) {
  Entry& entry = Add(name, help, label_names);  // before label_names moves
  return NewFamily<Gauge>(entry, std::move(label_names), [] { return std::make_unique<Gauge>(); });
}

Family<Histogram>& Registry::Histograms(const std::string& name, const std::string& help,
                                        std::vector<double> bounds,
                                        std::vector<std::string> label_names) {
  Histogram check(bounds);  // throws on bad bounds now, not at the first label set
  Entry& entry = Add(name, help, label_names);  // before label_names moves
  return NewFamily<Histogram>(entry, std::move(label_names),
                              [bounds] { return std::make_unique<Histogram>(bounds); });
}

void Registry::GaugeFunction(const std::string& name, const std::string& help,
                             std::function<double()> read) {
  Add(name, help, {}).metrics = std::move(read);
}

namespace {

void WriteHistogram(TextWriter& out, const std::string& name, const Labels& labels,
                    const Histogram& histogram) {
  Labels bucket_labels = labels;
  bucket_labels.emplace_back("le", "");
  const std::vector<double>& bounds = histogram.bounds();
  for (size_t i = 0; i <= bounds.size(); ++i) {
    bucket_labels.back().second =
        FormatValue(i < bounds.size() ? bounds[i] : std::numeric_limits<double>::infinity());
    out.Sample(name + "_bucket", bucket_labels, static_cast<double>(histogram.CumulativeCount(i)));
  }
  out.Sample(name + "_sum", labels, histogram.sum());
  out.Sample(name + "_count", labels, static_cast<double>(histogram.count()));
}

}  // namespace

std::string Registry::Exposition() const {
  TextWriter out;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const std::unique_ptr<Entry>& entry : entries_) {
    const std::string& name = entry->name;
    if (const auto* counters = std::get_if<0>(&entry->metrics)) {
      out.Family(name, entry->help, "counter");
      (*counters)->ForEach(
          [&](const Labels& labels, const Counter& c) { out.Sample(name, labels, c.value()); });
    } else if (const auto* gauges = std::get_if<1>(&entry->metrics)) {
      out.Family(name, entry->help, "gauge");
      (*gauges)->ForEach(
          [&](const Labels& labels, const Gauge& g) { out.Sample(name, labels, g.value()); });
    } else if (const auto* histograms = std::get_if<2>(&entry->metrics)) {
      out.Family(name, entry->help, "histogram");
      (*histograms)->ForEach([&](const Labels& labels, const Histogram& h) {
        WriteHistogram(out, name, labels, h);
      });
    } else {
      out.Family(name, entry->help, "gauge");
      out.Sample(name, {}, std::get<3>(entry->metrics)());
    }
  }
  return out.text();
}

}  // namespace mbstream::metrics
