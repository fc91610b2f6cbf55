// parse_json_text (declared in scene_json.hpp): JSON text -> nlohmann::json through our own SAX
// builder, so the depth limit, duplicate keys and non-finite numbers are caught while parsing, before
// a hostile body (100k nested arrays) can build anything large or recurse deeply.
#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_json.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace rr {

using nlohmann::json;

namespace {

// Builds the tree like nlohmann's own DOM parser. Pointers to open containers stay valid because a
// parent is not modified while one of its children is open.
class BoundedBuilder {
 public:
  // `nul_at`: the offset of the first NUL byte in the text, where parsing was cut (npos: none).
  BoundedBuilder(json& root, size_t max_depth, size_t nul_at) : root_(root), max_depth_(max_depth), nul_at_(nul_at) {}

  bool null() { return add(json(nullptr)); }
  bool boolean(bool v) { return add(json(v)); }
  bool number_integer(json::number_integer_t v) { return add(json(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return add(json(v)); }
  bool number_float(json::number_float_t v, const std::string& /*text*/) {
    // nlohmann's lexer turns 1e999 into inf; JSON has no such value and we cannot render it.
    if (!std::isfinite(v)) fail(current_pointer(), "number is too large for a double");
    return add(json(v));
  }
  bool string(std::string& v) { return add(json(std::move(v))); }
  bool binary(json::binary_t& /*v*/) { return add(json(nullptr)); }  // never sent by the text lexer

  bool start_object(size_t /*elements*/) { return open(json::object()); }
  bool start_array(size_t /*elements*/) { return open(json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(std::string& k) {
    Frame& top = stack_.back();
    if (top.container->contains(k)) {
      fail(pointer_append(container_pointer(stack_.size() - 1), k), "duplicate key");
    }
    top.key = std::move(k);
    return true;
  }

  // Syntax errors, invalid UTF-8, and numbers that overflow a double (nlohmann 3.11 reports those
  // itself). The pointer is "": text that is not JSON has no reliable location in a JSON tree.
  bool parse_error(size_t position, const std::string& /*last_token*/, const json::exception& ex) {
    // Running out of text where the NUL cut it is the NUL's fault, not a truncated body's.
    if (nul_at_ != std::string::npos && position > nul_at_) fail_at_nul();
    fail("", "invalid JSON at byte " + std::to_string(position) + ": " + printable_reason(ex.what()));
  }

  // Byte offsets count from 1, as nlohmann's positions in the other syntax errors do.
  [[noreturn]] void fail_at_nul() const {
    fail("", "invalid JSON at byte " + std::to_string(nul_at_ + 1) +
                 ": a NUL byte (JSON text may hold nothing but whitespace after its value, and no raw "
                 "control characters inside it)");
  }

 private:
  struct Frame {
    json* container;
    std::string key;  // objects: the key of the value being read
  };

  // nlohmann's message without its "[json.exception.parse_error.101] " prefix, and with bytes outside
  // printable ASCII spelled \xNN: it quotes the offending text, which may be invalid UTF-8, and the
  // detail must be safe to put into a JSON problem body.
  // The quoted token ("last read: '...'") can be a whole multi-megabyte string, so it is cut as
  // quote_input would cut it before it is escaped.
  static std::string printable_reason(const std::string& what) {
    std::string_view reason = what;
    if (auto end = reason.find("] "); reason.starts_with("[json.") && end != std::string::npos) {
      reason.remove_prefix(end + 2);
    }
    constexpr std::string_view quote_open = "last read: '";
    size_t token_start = reason.find(quote_open);
    if (token_start == std::string_view::npos) return printable(reason);
    token_start += quote_open.size();
    // nlohmann appends "; expected ..." after the token on some errors; the token itself may hold "'".
    size_t token_end = reason.rfind("'; expected");
    if (token_end == std::string_view::npos || token_end < token_start) token_end = reason.rfind('\'');
    if (token_end == std::string_view::npos || token_end < token_start) token_end = reason.size();
    std::string_view token = reason.substr(token_start, token_end - token_start);
    size_t keep = quoted_input_length(token);
    std::string out = printable(reason.substr(0, token_start)) + printable(token.substr(0, keep));
    if (keep < token.size()) out += truncation_marker(token.size());
    return out + printable(reason.substr(token_end));
  }

  // Bytes outside printable ASCII spelled \xNN.
  static std::string printable(std::string_view text) {
    std::string out;
    for (char c : text) {
      auto byte = static_cast<unsigned char>(c);
      if (byte >= 0x20 && byte < 0x7f) {
        out += char(byte);
      } else {
        char escaped[8];
        std::snprintf(escaped, sizeof escaped, "\\x%02X", unsigned(byte));
        out += escaped;
      }
    }
    return out;
  }

  [[noreturn]] static void fail(const std::string& pointer, const std::string& detail) {
    throw InputError(InputError::Kind::malformed, pointer, detail);
  }

  // The pointer of the open container at stack depth `level` (0 = the root). Each ancestor array's
  // open child is its last element.
  std::string container_pointer(size_t level) const {
    std::string pointer;
    for (size_t i = 0; i < level; ++i) {
      const Frame& frame = stack_[i];
      pointer = frame.container->is_array() ? pointer_append(pointer, frame.container->size() - 1)
                                            : pointer_append(pointer, frame.key);
    }
    return pointer;
  }

  // Where the next value will go.
  std::string current_pointer() const {
    if (stack_.empty()) return "";
    const Frame& top = stack_.back();
    std::string parent = container_pointer(stack_.size() - 1);
    return top.container->is_array() ? pointer_append(parent, top.container->size()) : pointer_append(parent, top.key);
  }

  json* place(json&& value) {
    if (stack_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    json& parent = *stack_.back().container;
    if (parent.is_array()) {
      parent.push_back(std::move(value));
      return &parent.back();
    }
    json& slot = parent[stack_.back().key];
    slot = std::move(value);
    return &slot;
  }

  bool add(json&& value) {
    place(std::move(value));
    return true;
  }

  bool open(json&& container) {
    if (stack_.size() + 1 > max_depth_) {
      fail(current_pointer(), "nesting is deeper than " + std::to_string(max_depth_) + " levels");
    }
    json* placed = place(std::move(container));
    stack_.push_back({placed, {}});
    return true;
  }

  bool close() {
    stack_.pop_back();
    return true;
  }

  json& root_;
  size_t max_depth_;
  size_t nul_at_;
  std::vector<Frame> stack_;
};

}  // namespace

json parse_json_text(std::string_view text, const ParseLimits& limits) {
  // nlohmann's lexer takes a NUL byte for the end of input, so "{}\0{...}" would parse as "{}" and
  // drop the rest. JSON has no place for a raw NUL (strings must escape it), so the text is parsed
  // up to the first NUL and the NUL itself is then the error, whatever precedes it.
  size_t nul = text.find('\0');
  json root;
  BoundedBuilder builder(root, limits.max_depth, nul);
  json::sax_parse(text.begin(), text.begin() + std::ptrdiff_t(std::min(nul, text.size())), &builder);
  if (nul != std::string_view::npos) builder.fail_at_nul();
  return root;
}

}  // namespace rr
