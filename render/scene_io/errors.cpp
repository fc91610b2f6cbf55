// InputError's one-line summary, and JSON Pointer building for it (RFC 6901): a reference token
// escapes '~' as "~0" and '/' as "~1". '~' is replaced first in spirit: each character is escaped on
// its own, so "~1" in a key becomes "~01" and reads back as the original two characters. Long client
// text is cut here too (quote_input), since pointers and messages quoting it go into answers.
#include "render/scene_io/errors.hpp"

namespace rr {

InputError::InputError(Kind kind, std::vector<FieldProblem> errors, bool truncated)
    : std::runtime_error(errors.empty() ? std::string() : errors.front().detail),
      kind_(kind),
      errors_(errors.empty() ? std::vector<FieldProblem>{FieldProblem{}} : std::move(errors)),
      truncated_(truncated) {}

std::string InputError::summary() const {
  const FieldProblem& first = errors_.front();
  std::string out = first.pointer.empty() ? first.detail : first.pointer + ": " + first.detail;
  const size_t more = errors_.size() - 1;
  if (truncated_) {
    out += " (and " + std::to_string(more) + " more listed; the list stops at " + std::to_string(errors_.size()) + ")";
  } else if (more > 0) {
    out += " (and " + std::to_string(more) + (more == 1 ? " more error)" : " more errors)");
  }
  return out;
}

size_t quoted_input_length(std::string_view text) {
  if (text.size() <= max_quoted_input_bytes) return text.size();
  size_t cut = max_quoted_input_bytes;
  // Back off continuation bytes (10xxxxxx) so the cut falls before a lead byte; a UTF-8 sequence
  // has at most 3 of them, and invalid text stops the walk after that many.
  for (int step = 0; step < 3 && cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80; ++step) {
    --cut;
  }
  return cut;
}

std::string truncation_marker(size_t total_bytes) { return "\u2026(" + std::to_string(total_bytes) + " bytes)"; }

std::string quote_input(std::string_view text) {
  size_t keep = quoted_input_length(text);
  std::string out(text.substr(0, keep));
  if (keep < text.size()) out += truncation_marker(text.size());
  return out;
}

std::string pointer_append(const std::string& pointer, const std::string& raw_token) {
  const std::string token = quote_input(raw_token);
  std::string out;
  out.reserve(pointer.size() + token.size() + 1);
  out += pointer;
  out += '/';
  for (char c : token) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

std::string pointer_append(const std::string& pointer, size_t index) { return pointer + '/' + std::to_string(index); }

}  // namespace rr
