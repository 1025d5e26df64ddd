#pragma once
// The tests' own reader of what io::write_ply writes (binary little-endian, one vertex element,
// scalar properties), so that a PLY a test writes is read back and its values checked. The
// project has no PLY reader: PLY is an export for other tools (Open3D reads the same files in
// tests/python/test_export_tools.py).

#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fmcw::test {

struct PlyVertices {
  std::vector<std::string> comments;
  std::vector<std::string> names;                      ///< properties in file order
  std::map<std::string, std::string> types;            ///< name -> PLY type ("float", "uchar", ...)
  std::map<std::string, std::vector<double>> values;   ///< name -> one value per vertex
  std::size_t count = 0;
};

/// Reads a binary little-endian PLY of one vertex element; std::runtime_error on anything else.
inline PlyVertices read_ply(const std::string& path) {
  static const std::map<std::string, int> kSizes = {{"char", 1},  {"uchar", 1}, {"short", 2}, {"ushort", 2},
                                                    {"int", 4},   {"uint", 4},  {"float", 4}, {"double", 8}};
  std::ifstream in(path, std::ios::binary);
  const auto fail = [&](const std::string& what) { throw std::runtime_error(path + ": " + what); };
  std::string line;
  if (!std::getline(in, line) || line != "ply") fail("not a PLY file");
  if (!std::getline(in, line) || line != "format binary_little_endian 1.0") fail("not binary little-endian: " + line);
  PlyVertices ply;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string key, a, b;
    words >> key >> a >> b;
    if (key == "comment") {
      ply.comments.push_back(line.substr(8));
    } else if (key == "element") {
      if (a != "vertex" || !ply.names.empty()) fail("unexpected element line: " + line);
      ply.count = std::stoul(b);
    } else if (key == "property") {
      if (!kSizes.count(a)) fail("unknown property type: " + line);
      ply.names.push_back(b);
      ply.types[b] = a;
    } else {
      fail("unexpected header line: " + line);
    }
  }
  if (line != "end_header") fail("no end_header");
  for (std::size_t v = 0; v < ply.count; ++v) {
    for (const std::string& name : ply.names) {
      const std::string& type = ply.types[name];
      char bytes[8] = {};
      if (!in.read(bytes, kSizes.at(type))) fail("ends inside vertex " + std::to_string(v));
      std::uint64_t bits = 0;
      for (int k = kSizes.at(type) - 1; k >= 0; --k) bits = (bits << 8) | static_cast<unsigned char>(bytes[k]);
      double value = 0.0;
      if (type == "float") {
        float f = 0.0f;
        const auto b32 = static_cast<std::uint32_t>(bits);
        std::memcpy(&f, &b32, 4);
        value = f;
      } else if (type == "double") {
        std::memcpy(&value, &bits, 8);
      } else if (type == "char" || type == "short" || type == "int") {
        const int shift = 64 - 8 * kSizes.at(type);
        value = static_cast<double>(static_cast<std::int64_t>(bits << shift) >> shift);
      } else {
        value = static_cast<double>(bits);
      }
      ply.values[name].push_back(value);
    }
  }
  if (in.peek() != std::char_traits<char>::eof()) fail("bytes after the last vertex");
  return ply;
}

}  // namespace fmcw::test
