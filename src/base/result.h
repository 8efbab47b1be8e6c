// Value-or-error for load-time operations (never used inside the frame loop).
#pragma once

#include <optional>
#include <string>
#include <utility>

namespace mar {

template <class T>
struct Result {
  std::optional<T> value;
  std::string error;
  bool ok() const { return value.has_value(); }
  static Result success(T v) { return Result{std::move(v), {}}; }
  static Result failure(std::string e) { return Result{std::nullopt, std::move(e)}; }
};

}  // namespace mar
