#pragma once
// The 64-bit FNV-1a hash of a text: the stored configs' fingerprint (checkpoints, saved
// simulations, the source of a continued run). Not cryptographic: it detects edits, not forgery.
#include <cstdint>
#include <string>

namespace granboltz {

inline std::uint64_t text_hash(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (const unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

}  // namespace granboltz
