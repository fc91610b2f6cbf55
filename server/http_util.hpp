// Small pieces of HTTP semantics the service needs and cpp-httplib does not provide: media types,
// Accept negotiation (RFC 9110 12.5.1), entity-tag matching for If-None-Match (RFC 9110 13.1.2),
// content hashes for ids and ETags, and base64 for JSON render answers. Pure functions on strings.
#pragma once

#include "render/core/hash.hpp"

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace rr::server {

std::string lowercase(std::string_view s);

// "application/json; charset=utf-8" -> "application/json" (lowercase, parameters dropped).
std::string media_type(std::string_view content_type);

// The first of `offered` (in the server's order of preference) with the highest q-value in `accept`,
// or nullopt when the header rules every one out (q=0 or no matching range): 406. A missing or blank
// header accepts anything, so the first offer wins.
std::optional<std::string> negotiate(std::string_view accept, std::span<const std::string> offered);

// True when an If-None-Match value matches `etag`: "*", or any listed tag by weak comparison (the
// W/ prefix is ignored, as RFC 9110 asks for If-None-Match).
bool if_none_match_matches(std::string_view if_none_match, std::string_view etag);

// 16 lowercase hex digits of the 64-bit FNV-1a hash of `bytes` (render/core/hash.hpp): stored-scene
// ids and ETags.
using rr::hash_hex;

std::string base64_encode(std::string_view bytes);

}  // namespace rr::server
