// HTTP helpers (see http_util.hpp). Parsing is lenient about whitespace and strict about meaning: a
// q-value that is not a number in [0, 1] makes its range count as q=1, as most servers do.
#include "server/http_util.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <vector>

namespace rr::server {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Splits on `separator` outside double quotes (entity tags and parameters may quote commas).
std::vector<std::string_view> split_list(std::string_view s, char separator) {
  std::vector<std::string_view> parts;
  size_t start = 0;
  bool quoted = false;
  for (size_t i = 0; i <= s.size(); ++i) {
    if (i < s.size() && s[i] == '"') quoted = !quoted;
    if (i == s.size() || (s[i] == separator && !quoted)) {
      if (auto part = trim(s.substr(start, i - start)); !part.empty()) parts.push_back(part);
      start = i + 1;
    }
  }
  return parts;
}

struct MediaRange {
  std::string type;     // "image", or "*"
  std::string subtype;  // "png", or "*"
  double q = 1.0;
};

std::optional<MediaRange> parse_range(std::string_view text) {
  std::vector<std::string_view> parts = split_list(text, ';');
  if (parts.empty()) return std::nullopt;
  std::string full = lowercase(parts[0]);
  size_t slash = full.find('/');
  if (slash == std::string::npos) return std::nullopt;
  MediaRange range{full.substr(0, slash), full.substr(slash + 1), 1.0};
  for (size_t i = 1; i < parts.size(); ++i) {
    size_t eq = parts[i].find('=');
    if (eq == std::string_view::npos || lowercase(trim(parts[i].substr(0, eq))) != "q") continue;
    std::string_view value = trim(parts[i].substr(eq + 1));
    double q = 1.0;
    auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), q);
    if (ec == std::errc() && end == value.data() + value.size() && q >= 0.0 && q <= 1.0) range.q = q;
  }
  return range;
}

// How well `range` matches "type/subtype": 3 exact, 2 type/*, 1 */*, 0 not at all.
int specificity(const MediaRange& range, std::string_view offered) {
  size_t slash = offered.find('/');
  std::string_view type = offered.substr(0, slash), subtype = offered.substr(slash + 1);
  if (range.type == "*" && range.subtype == "*") return 1;
  if (range.type != type) return 0;
  if (range.subtype == "*") return 2;
  return range.subtype == subtype ? 3 : 0;
}

}  // namespace

std::string lowercase(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return out;
}

std::string media_type(std::string_view content_type) {
  return lowercase(trim(content_type.substr(0, content_type.find(';'))));
}

std::optional<std::string> negotiate(std::string_view accept, std::span<const std::string> offered) {
  if (offered.empty()) return std::nullopt;
  if (trim(accept).empty()) return offered[0];
  std::vector<MediaRange> ranges;
  for (std::string_view part : split_list(accept, ',')) {
    if (auto range = parse_range(part)) ranges.push_back(*range);
  }
  if (ranges.empty()) return offered[0];  // nothing readable: treat as absent
  std::optional<std::string> best;
  double best_q = 0.0;
  for (const std::string& type : offered) {
    int best_specificity = 0;
    double q = 0.0;
    for (const MediaRange& range : ranges) {  // the most specific matching range sets the q-value
      int s = specificity(range, type);
      if (s > best_specificity) {
        best_specificity = s;
        q = range.q;
      }
    }
    if (q > best_q) {
      best_q = q;
      best = type;
    }
  }
  return best;
}

bool if_none_match_matches(std::string_view if_none_match, std::string_view etag) {
  auto opaque = [](std::string_view tag) {
    tag = trim(tag);
    if (tag.starts_with("W/")) tag.remove_prefix(2);
    return tag;
  };
  for (std::string_view candidate : split_list(if_none_match, ',')) {
    if (candidate == "*" || opaque(candidate) == opaque(etag)) return true;
  }
  return false;
}

std::string base64_encode(std::string_view bytes) {
  static constexpr char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
    for (int shift : {18, 12, 6, 0}) out += alphabet[(v >> shift) & 63];
  }
  if (size_t rest = bytes.size() - i; rest > 0) {
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | (rest == 2 ? uint32_t(uint8_t(bytes[i + 1])) << 8 : 0);
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += rest == 2 ? alphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

}  // namespace rr::server
