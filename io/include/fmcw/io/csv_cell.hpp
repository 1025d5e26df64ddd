#pragma once
// A text cell of a CSV table, as RFC 4180 writes it.

#include <string>

namespace fmcw::io {

/// text as it is when it holds no comma, double quote or line break; otherwise in double quotes,
/// each double quote doubled (RFC 4180, section 2.6-2.7).
inline std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string q = "\"";
  for (const char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace fmcw::io
