// SPDX-License-Identifier: Apache-2.0
#include "result_codec.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace dvi::internal {
namespace {

class Writer {
 public:
  explicit Writer(std::string& bytes) : bytes_(bytes) {}

  template <typename T>
  void Put(T value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void Put(const std::string& text) {
    Put<std::uint64_t>(text.size());
    bytes_.append(text);
  }
  void Put(const double* values, std::size_t count) {
    Put<std::uint64_t>(count);
    bytes_.append(reinterpret_cast<const char*>(values), count * sizeof(double));
  }
  void Put(const Eigen::VectorXd& v) { Put(v.data(), static_cast<std::size_t>(v.size())); }
  void Put(const std::vector<double>& v) { Put(v.data(), v.size()); }
  void Put(const VectorSamples& samples) {
    Put<std::int64_t>(samples.dim());
    Put<std::uint64_t>(samples.size());
    const auto values = samples.matrix();
    bytes_.append(reinterpret_cast<const char*>(values.data()),
                  static_cast<std::size_t>(values.size()) * sizeof(double));
  }
  // Structs with padding go field by field (no uninitialized bytes travel);
  // IntegrationStats holds only 8-byte fields.
  void Put(const IntegrationStats& stats) {
    static_assert(sizeof(IntegrationStats) % 8 == 0 && alignof(IntegrationStats) == 8);
    Put<IntegrationStats>(stats);
  }
  void Put(const CertifiedMeasure& measure) {
    Put(measure.value);
    Put(measure.bound);
    Put(measure.ratio);
    Put(measure.time);
    Put(measure.component);
    Put(measure.checked);
  }
  void Put(const Event& event) {
    Put(event.time);
    Put<int>(static_cast<int>(event.kind));
    Put(event.index);
    Put(event.impulse);
  }
  void Put(const StepRecord& record) {
    Put(record.t);
    Put(record.h);
    Put(record.iterations);
    Put(record.residual);
  }

 private:
  std::string& bytes_;
};

class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  bool done() const { return at_ == bytes_.size(); }

  template <typename T>
  T Get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, Take(sizeof(T)), sizeof(T));
    return value;
  }
  // A length prefix, checked against what is left before anything is sized
  // by it (each element takes at least element_bytes).
  std::size_t GetLength(std::size_t element_bytes) {
    const auto count = Get<std::uint64_t>();
    if (count > Remaining() / element_bytes) throw std::runtime_error("ensemble results: malformed length");
    return static_cast<std::size_t>(count);
  }
  std::string GetString() {
    const std::size_t size = GetLength(1);
    return std::string(Take(size), size);
  }
  std::vector<double> GetDoubles() {
    const std::size_t count = GetLength(sizeof(double));
    std::vector<double> values(count);
    if (count > 0) std::memcpy(values.data(), Take(count * sizeof(double)), count * sizeof(double));
    return values;
  }
  Eigen::VectorXd GetVector() {
    const std::vector<double> values = GetDoubles();
    return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  }
  CertifiedMeasure GetMeasure() {
    CertifiedMeasure measure;
    measure.value = Get<double>();
    measure.bound = Get<double>();
    measure.ratio = Get<double>();
    measure.time = Get<double>();
    measure.component = Get<int>();
    measure.checked = Get<long>();
    return measure;
  }
  Event GetEvent() {
    Event event;
    event.time = Get<double>();
    event.kind = static_cast<EventKind>(Get<int>());
    event.index = Get<int>();
    event.impulse = GetVector();
    return event;
  }
  StepRecord GetStepRecord() {
    StepRecord record;
    record.t = Get<double>();
    record.h = Get<double>();
    record.iterations = Get<int>();
    record.residual = Get<double>();
    return record;
  }
  VectorSamples GetSamples() {
    const auto dim = Get<std::int64_t>();
    const auto size = Get<std::uint64_t>();
    if (dim < 0 || (dim > 0 && size > Remaining() / (sizeof(double) * static_cast<std::size_t>(dim))))
      throw std::runtime_error("ensemble results: malformed samples");
    VectorSamples samples;
    samples.reserve(size, dim);
    if (size > 0 && dim > 0) {
      auto block = samples.Extend(size, dim);
      std::memcpy(block.data(), Take(size * static_cast<std::size_t>(dim) * sizeof(double)),
                  size * static_cast<std::size_t>(dim) * sizeof(double));
    } else if (size > 0) {
      samples.Extend(size, dim);
    }
    return samples;
  }

 private:
  std::size_t Remaining() const { return bytes_.size() - at_; }
  const char* Take(std::size_t size) {
    if (size > Remaining()) throw std::runtime_error("ensemble results: truncated buffer");
    const char* begin = bytes_.data() + at_;
    at_ += size;
    return begin;
  }

  const std::string& bytes_;
  std::size_t at_ = 0;
};

void PutTrajectory(const Trajectory& trajectory, Writer& out) {
  out.Put<int>(static_cast<int>(trajectory.status));
  out.Put(trajectory.message);
  out.Put(trajectory.times);
  out.Put(trajectory.states);
  out.Put(trajectory.multipliers);
  out.Put<std::uint64_t>(trajectory.events.size());
  for (const Event& event : trajectory.events) out.Put(event);
  out.Put<std::uint64_t>(trajectory.intervals.size());
  for (const MethodInterval& interval : trajectory.intervals) {
    out.Put(interval.from);
    out.Put(interval.to);
    out.Put<int>(static_cast<int>(interval.method));
    out.Put(interval.reason);
  }
  out.Put<std::uint64_t>(trajectory.step_log.size());
  for (const StepRecord& record : trajectory.step_log) out.Put(record);
  out.Put(trajectory.stats);
  const Certificate& certificate = trajectory.certificate;
  out.Put<bool>(certificate.evaluated);
  out.Put(certificate.vi);
  out.Put(certificate.ode);
  out.Put(certificate.window);
  out.Put(certificate.basis);
}

Trajectory GetTrajectory(Reader& in) {
  Trajectory trajectory;
  trajectory.status = static_cast<IntegrationStatus>(in.Get<int>());
  trajectory.message = in.GetString();
  trajectory.times = in.GetDoubles();
  trajectory.states = in.GetSamples();
  trajectory.multipliers = in.GetSamples();
  trajectory.events.resize(in.GetLength(24));
  for (Event& event : trajectory.events) event = in.GetEvent();
  trajectory.intervals.resize(in.GetLength(28));
  for (MethodInterval& interval : trajectory.intervals) {
    interval.from = in.Get<double>();
    interval.to = in.Get<double>();
    interval.method = static_cast<IntegrationMethod>(in.Get<int>());
    interval.reason = in.GetString();
  }
  trajectory.step_log.resize(in.GetLength(28));
  for (StepRecord& record : trajectory.step_log) record = in.GetStepRecord();
  trajectory.stats = in.Get<IntegrationStats>();
  Certificate& certificate = trajectory.certificate;
  certificate.evaluated = in.Get<bool>();
  certificate.vi = in.GetMeasure();
  certificate.ode = in.GetMeasure();
  certificate.window = in.GetMeasure();
  certificate.basis = in.GetString();
  return trajectory;
}

}  // namespace

void AppendResult(const EnsembleResult& result, std::string& bytes) {
  Writer out(bytes);
  out.Put<std::uint64_t>(result.member);
  out.Put<int>(static_cast<int>(result.status));
  out.Put(result.message);
  out.Put<bool>(result.refused);
  out.Put(result.t_final);
  out.Put(result.x_final);
  out.Put<std::uint64_t>(result.events);
  out.Put(result.stats);
  out.Put<bool>(result.certified);
  out.Put(result.reduction);
  out.Put<bool>(result.trajectory.has_value());
  if (result.trajectory) PutTrajectory(*result.trajectory, out);
}

std::vector<EnsembleResult> ReadResults(const std::string& bytes) {
  Reader in(bytes);
  std::vector<EnsembleResult> results;
  while (!in.done()) {
    EnsembleResult& result = results.emplace_back();
    result.member = in.Get<std::uint64_t>();
    result.status = static_cast<IntegrationStatus>(in.Get<int>());
    result.message = in.GetString();
    result.refused = in.Get<bool>();
    result.t_final = in.Get<double>();
    result.x_final = in.GetVector();
    result.events = in.Get<std::uint64_t>();
    result.stats = in.Get<IntegrationStats>();
    result.certified = in.Get<bool>();
    result.reduction = in.GetDoubles();
    if (in.Get<bool>()) result.trajectory = GetTrajectory(in);
  }
  return results;
}

}  // namespace dvi::internal
