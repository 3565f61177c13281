// The AFF tokenizer: whitespace-separated tokens over a whole-file buffer
// (the BART scenes are megabytes of numbers, hence inline), `{` and `}` as
// tokens of their own, `#` and `%` comments, and typed reads whose errors
// name the file and line. Internal to the AFF loader.
#pragma once

#include <cfloat>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "nodetrace/tracer/scene/scene_loader.hpp"
#include "nodetrace/tracer/geometry/vec3.hpp"

namespace nodetrace::tracer::detail::aff {

class Tokenizer {
 public:
  Tokenizer(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {}

  // The next token ("" at the end). `{` and `}` are tokens of their own;
  // `#` and `%` start a comment running to the end of the line.
  std::string_view next() {
    skip_space();
    token_line_ = line_;
    if (pos_ >= text_.size()) return {};
    const std::size_t start = pos_;
    if (text_[pos_] == '{' || text_[pos_] == '}') return text_.substr(pos_++, 1);
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v' || c == '#' ||
          c == '%' || c == '{' || c == '}') {
        break;
      }
      ++pos_;
    }
    return text_.substr(start, pos_ - start);
  }

  std::string_view peek() {
    const std::size_t pos = pos_;
    const int line = line_, token_line = token_line_;
    const std::string_view token = next();
    pos_ = pos, line_ = line, token_line_ = token_line;
    return token;
  }

  static std::optional<double> parse_number(std::string_view token) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    double value = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size() || token.empty()) return std::nullopt;
    return value;
  }

  double number(std::string_view what) {
    const std::string_view token = next();
    last_token_ = token;
    if (token.empty()) fail("expected " + std::string(what) + ", got the end of the file");
    const auto value = parse_number(token);
    if (!value) fail("expected " + std::string(what) + " (a number), got '" + std::string(token) + "'");
    if (!std::isfinite(*value)) {
      fail("expected " + std::string(what) + " (a finite number), got '" + std::string(token) + "'");
    }
    return *value;
  }

  // A number stored as a float: one beyond FLT_MAX would become inf.
  float real(std::string_view what) {
    const double value = number(what);
    if (std::fabs(value) > FLT_MAX) {
      fail(fmt::format("expected {} (a number of at most {:g} in magnitude), got '{}'", what, FLT_MAX,
                       std::string(last_token_)));
    }
    return static_cast<float>(value);
  }

  Vec3 vec3(std::string_view what) {
    const float x = real(what), y = real(what), z = real(what);
    return {x, y, z};
  }

  // A material's or light's number: a negative one would give negative
  // radiance, so it is refused (named with its line and value).
  float non_negative(std::string_view what) {
    const float value = real(what);
    if (value < 0) {
      fail(fmt::format("expected {} (a number of at least 0), got '{}'", what, std::string(last_token_)));
    }
    return value;
  }

  Vec3 non_negative_vec3(std::string_view what) {
    const float x = non_negative(what), y = non_negative(what), z = non_negative(what);
    return {x, y, z};
  }

  // A count of elements that follow in the file, `tokens_per_element`
  // tokens each: each token takes at least two bytes (a character and a
  // separator), so a count the rest of the file cannot hold is an error
  // before anything is allocated for it.
  std::size_t count(std::string_view what, std::size_t limit = 100'000'000, std::size_t tokens_per_element = 0) {
    const std::string_view token = next();
    std::size_t value = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (token.empty() || error != std::errc() || end != token.data() + token.size() || value > limit) {
      fail("expected " + std::string(what) + " (a non-negative integer), got '" + std::string(token) + "'");
    }
    const std::size_t remaining = text_.size() - pos_;
    if (tokens_per_element > 0 && value > remaining / (2 * tokens_per_element)) {
      fail(fmt::format("{} {} needs at least {} bytes, more than the {} left before the end of the file", what,
                       value, 2 * tokens_per_element * value, remaining));
    }
    return value;
  }

  std::string word(std::string_view what) {
    const std::string_view token = next();
    if (token.empty() || token == "{" || token == "}") {
      fail("expected " + std::string(what) + ", got '" + std::string(token) + "'");
    }
    return std::string(token);
  }

  void expect(std::string_view wanted) {
    const std::string_view token = next();
    if (token != wanted) {
      fail(fmt::format("expected '{}', got {}", wanted, describe(token)));
    }
  }

  // A token as an error names it: quoted, or "the end of the file". (fmt, not
  // "'" + std::string(...): GCC 12 warns falsely (-Wrestrict) on that inlined.)
  static std::string describe(std::string_view token) {
    return token.empty() ? std::string("the end of the file") : fmt::format("'{}'", token);
  }

  [[noreturn]] void fail(const std::string& what) const { fail_at(token_line_, what); }
  [[noreturn]] void fail_at(int line, const std::string& what) const {
    throw SceneError(file_ + ":" + std::to_string(line) + ": " + what);
  }

  int line() const { return token_line_; }
  const std::string& file() const { return file_; }

 private:
  void skip_space() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_, ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++pos_;
      } else if (c == '#' || c == '%') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
  }

  std::string_view text_;
  std::string file_;
  std::string_view last_token_;  // of number()
  std::size_t pos_ = 0;
  int line_ = 1, token_line_ = 1;
};

}  // namespace nodetrace::tracer::detail::aff
