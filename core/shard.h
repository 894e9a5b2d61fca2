// A share of a stage's work, for running it as several jobs (docs/workflow.md): shard I of N
// takes a contiguous, balanced range of the work's items, so the shards together take every item
// once and their outputs, concatenated in shard order, are the items in order.
#pragma once

#include <cerrno>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>

namespace mesocap {

struct Shard {
  int index = 1, count = 1;  // 1 <= index <= count

  // Items [first, second) of `total`: sizes differ by at most one.
  std::pair<size_t, size_t> Range(size_t total) const {
    return {total * size_t(index - 1) / size_t(count), total * size_t(index) / size_t(count)};
  }
  std::string Name() const { return std::to_string(index) + "/" + std::to_string(count); }

  // "I/N" with 1 <= I <= N <= kMaxCount, nothing else; nullopt otherwise.
  static constexpr int kMaxCount = 999;
  static std::optional<Shard> Parse(const std::string& text) {
    const size_t slash = text.find('/');
    if (slash == std::string::npos) return std::nullopt;
    const auto number = [](const std::string& digits) -> long {
      if (digits.empty() || digits.size() > 4 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
      return std::strtol(digits.c_str(), nullptr, 10);
    };
    const long index = number(text.substr(0, slash)), count = number(text.substr(slash + 1));
    if (index < 1 || count < index || count > kMaxCount) return std::nullopt;
    return Shard{int(index), int(count)};
  }
};

}  // namespace mesocap
