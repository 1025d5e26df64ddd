#include "fmcw/io/npz.hpp"

#include <cstring>
#include <memory>
#include <sstream>

#include "fmcw/core/check.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/input_file.hpp"

#ifdef FMCW_HAVE_LIBZIP
#include <zip.h>
#endif

namespace fmcw::io {

using core::concat;

namespace {

constexpr char kMagic[] = "\x93NUMPY";

// The value after 'key': in a .npy header dict, up to the next delimiter.
std::string dict_value(const std::string& dict, const std::string& key, const std::string& source) {
  const std::string quoted = "'" + key + "'";
  const std::size_t at = dict.find(quoted);
  if (at == std::string::npos) throw core::FileError(concat(source, ": .npy header has no ", quoted, ": ", dict));
  std::size_t v = dict.find(':', at + quoted.size());
  if (v == std::string::npos) throw core::FileError(concat(source, ": .npy header: no value for ", quoted));
  v = dict.find_first_not_of(' ', v + 1);
  if (v == std::string::npos) throw core::FileError(concat(source, ": .npy header: no value for ", quoted));
  if (dict[v] == '(') {
    const std::size_t end = dict.find(')', v);
    if (end == std::string::npos) throw core::FileError(concat(source, ": .npy header: unclosed shape"));
    return dict.substr(v, end - v + 1);
  }
  const std::size_t end = dict.find_first_of(",}", v);
  std::string value = dict.substr(v, end - v);
  while (!value.empty() && value.back() == ' ') value.pop_back();
  if (value.size() >= 2 && (value.front() == '\'' || value.front() == '"')) value = value.substr(1, value.size() - 2);
  return value;
}

std::vector<std::size_t> parse_shape(const std::string& text, const std::string& source) {
  std::vector<std::size_t> shape;
  std::string inner = text.substr(1, text.size() - 2);
  std::istringstream in(inner);
  std::string item;
  while (std::getline(in, item, ',')) {
    const std::size_t b = item.find_first_not_of(' ');
    if (b == std::string::npos) continue;
    char* end = nullptr;
    const unsigned long long d = std::strtoull(item.c_str() + b, &end, 10);
    if (end == item.c_str() + b || d > (1ULL << 40)) {
      throw core::FileError(concat(source, ": .npy shape ", text, " is not a list of sizes"));
    }
    shape.push_back(static_cast<std::size_t>(d));
  }
  return shape;
}

std::string shape_text(const std::vector<std::size_t>& shape) {
  std::string s = "(";
  for (std::size_t k = 0; k < shape.size(); ++k) s += (k ? ", " : "") + std::to_string(shape[k]);
  return s + (shape.size() == 1 ? ",)" : ")");
}

template <class T>
NpyArray make_numbers(const std::vector<T>& values, std::vector<std::size_t> shape, char kind) {
  static_assert(sizeof(T) <= 8, "npy numbers are at most 8 bytes");
  NpyArray a;
  a.kind = kind;
  a.item_bytes = sizeof(T);
  a.shape = std::move(shape);
  FMCW_CHECK_ARG(a.size() == values.size(), "npy: ", values.size(), " values for shape ", shape_text(a.shape));
  a.data.resize(values.size() * sizeof(T));
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &values[i], sizeof(T));  // the value's bytes; stored little-endian below
    if constexpr (sizeof(T) == 4) bits &= 0xFFFFFFFFu;
    for (std::size_t b = 0; b < sizeof(T); ++b) a.data[i * sizeof(T) + b] = static_cast<unsigned char>((bits >> (8 * b)) & 0xFFu);
  }
  return a;
}

std::uint64_t load_le(const unsigned char* p, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t b = 0; b < n; ++b) v |= static_cast<std::uint64_t>(p[b]) << (8 * b);
  return v;
}

}  // namespace

std::size_t NpyArray::size() const {
  std::size_t n = 1;
  for (const std::size_t d : shape) n *= d;
  return n;
}

namespace {
void refuse_pickled(char kind, const std::string& source) {
  if (kind == 'O') {
    throw core::FileError(concat(source, ": a pickled Python object array, which only Python can read (save it as a "
                                 "fixed-width unicode or a number array)"));
  }
}
}  // namespace

std::vector<double> NpyArray::to_doubles(const std::string& source) const {
  refuse_pickled(kind, source);
  if (kind == 'U') throw core::FileError(concat(source, ": expected numbers, got strings"));
  const std::size_t n = size();
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char* p = data.data() + i * item_bytes;
    const std::uint64_t bits = load_le(p, item_bytes);
    if (kind == 'f' && item_bytes == 4) {
      const auto b32 = static_cast<std::uint32_t>(bits);
      float f = 0.0f;
      std::memcpy(&f, &b32, 4);
      out[i] = f;
    } else if (kind == 'f') {
      double d = 0.0;
      std::memcpy(&d, &bits, 8);
      out[i] = d;
    } else if (kind == 'i') {
      const unsigned shift = static_cast<unsigned>(64 - 8 * item_bytes);
      out[i] = static_cast<double>(static_cast<std::int64_t>(bits << shift) >> shift);  // sign-extend
    } else {
      out[i] = static_cast<double>(bits);
    }
  }
  return out;
}

std::vector<std::string> NpyArray::to_strings(const std::string& source) const {
  refuse_pickled(kind, source);
  if (kind != 'U') throw core::FileError(concat(source, ": expected strings, got numbers"));
  const std::size_t n = size();
  const std::size_t chars = item_bytes / 4;
  std::vector<std::string> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < chars; ++c) {
      const auto code = static_cast<std::uint32_t>(load_le(data.data() + i * item_bytes + 4 * c, 4));
      if (code == 0) break;
      out[i].push_back(code < 128 ? static_cast<char>(code) : '?');
    }
  }
  return out;
}

NpyArray parse_npy(const std::string& bytes, const std::string& source) {
  if (bytes.size() < 10 || bytes.compare(0, 6, kMagic, 6) != 0) {
    throw core::FileError(concat(source, ": not a .npy array (no \\x93NUMPY magic)"));
  }
  const auto major = static_cast<unsigned char>(bytes[6]);
  const std::size_t len_bytes = major == 1 ? 2 : 4;
  if (major < 1 || major > 3 || bytes.size() < 8 + len_bytes) {
    throw core::FileError(concat(source, ": .npy format version ", static_cast<int>(major), " is not 1, 2 or 3"));
  }
  const auto header_len = static_cast<std::size_t>(load_le(reinterpret_cast<const unsigned char*>(bytes.data()) + 8, len_bytes));
  const std::size_t data_at = 8 + len_bytes + header_len;
  if (data_at > bytes.size()) throw core::FileError(concat(source, ": .npy header runs past the end of the data"));
  const std::string dict = bytes.substr(8 + len_bytes, header_len);
  const std::string descr = dict_value(dict, "descr", source);
  if (dict_value(dict, "fortran_order", source) != "False") {
    throw core::FileError(concat(source, ": Fortran-ordered arrays are not read (save with C order)"));
  }
  NpyArray a;
  a.shape = parse_shape(dict_value(dict, "shape", source), source);
  if (descr == "|O" || descr == "<O") {
    a.kind = 'O';  // pickled Python objects: kept as a name, refused when read
    return a;
  }
  if (descr.size() < 3 || (descr[0] != '<' && descr[0] != '|')) {
    throw core::FileError(concat(source, ": dtype '", descr, "' is not little-endian"));
  }
  a.kind = descr[1];
  const long width = std::strtol(descr.c_str() + 2, nullptr, 10);
  const bool number = (a.kind == 'f' && (width == 4 || width == 8)) ||
                      ((a.kind == 'i' || a.kind == 'u') && (width == 1 || width == 2 || width == 4 || width == 8)) ||
                      (a.kind == 'b' && width == 1);
  if (!number && !(a.kind == 'U' && width > 0 && width < 4096)) {
    throw core::FileError(concat(source, ": unsupported dtype '", descr, "'"));
  }
  a.item_bytes = static_cast<std::size_t>(a.kind == 'U' ? 4 * width : width);
  if (a.kind == 'b') a.kind = 'u';
  const std::size_t expected = a.size() * a.item_bytes;
  if (bytes.size() - data_at != expected) {
    throw core::FileError(concat(source, ": .npy shape ", shape_text(a.shape), " of '", descr, "' needs ", expected,
                                 " bytes of data, the array has ", bytes.size() - data_at));
  }
  a.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(data_at), bytes.end());
  return a;
}

std::string npy_bytes(const NpyArray& a) {
  const std::string descr = a.kind == 'U' ? "<U" + std::to_string(a.item_bytes / 4)
                                          : std::string("<") + a.kind + std::to_string(a.item_bytes);
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape_text(a.shape) + ", }";
  const std::size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict.push_back('\n');
  std::string out(kMagic, 6);
  out.push_back('\x01');
  out.push_back('\x00');
  out.push_back(static_cast<char>(dict.size() & 0xFFu));
  out.push_back(static_cast<char>((dict.size() >> 8) & 0xFFu));
  out += dict;
  out.append(reinterpret_cast<const char*>(a.data.data()), a.data.size());
  return out;
}

NpyArray npy_f32(const std::vector<float>& v, std::vector<std::size_t> shape) { return make_numbers(v, std::move(shape), 'f'); }
NpyArray npy_u32(const std::vector<std::uint32_t>& v, std::vector<std::size_t> shape) { return make_numbers(v, std::move(shape), 'u'); }
NpyArray npy_i64(const std::vector<std::int64_t>& v, std::vector<std::size_t> shape) { return make_numbers(v, std::move(shape), 'i'); }

NpyArray npy_strings(const std::vector<std::string>& values, std::vector<std::size_t> shape) {
  NpyArray a;
  a.kind = 'U';
  a.shape = std::move(shape);
  FMCW_CHECK_ARG(a.size() == values.size(), "npy: ", values.size(), " strings for shape ", shape_text(a.shape));
  std::size_t width = 1;
  for (const auto& s : values) width = std::max(width, s.size());
  a.item_bytes = 4 * width;
  a.data.assign(values.size() * a.item_bytes, 0);
  for (std::size_t i = 0; i < values.size(); ++i) {
    for (std::size_t c = 0; c < values[i].size(); ++c) a.data[i * a.item_bytes + 4 * c] = static_cast<unsigned char>(values[i][c]);
  }
  return a;
}

#ifdef FMCW_HAVE_LIBZIP
bool npz_supported() { return true; }

namespace {
std::string zip_message(int code) {
  zip_error_t error;
  zip_error_init_with_code(&error, code);
  std::string text = zip_error_strerror(&error);
  zip_error_fini(&error);
  return text;
}
}  // namespace

std::map<std::string, NpyArray> read_npz(const std::string& path) {
  regular_file_size(path, ".npz file");
  int code = 0;
  std::unique_ptr<zip_t, void (*)(zip_t*)> archive(zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &code),
                                                     [](zip_t* z) { zip_discard(z); });
  if (!archive) throw core::FileError(concat(path, ": not a readable .npz (zip) archive: ", zip_message(code)));
  std::map<std::string, NpyArray> arrays;
  const zip_int64_t entries = zip_get_num_entries(archive.get(), 0);
  for (zip_int64_t e = 0; e < entries; ++e) {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(archive.get(), static_cast<zip_uint64_t>(e), 0, &st) != 0 || !(st.valid & ZIP_STAT_NAME) ||
        !(st.valid & ZIP_STAT_SIZE)) {
      throw core::FileError(concat(path, ": member ", e, ": ", zip_strerror(archive.get())));
    }
    const std::string member = st.name;
    const std::string where = concat(path, ": ", member);
    if (member.size() < 5 || member.compare(member.size() - 4, 4, ".npy") != 0) {
      throw core::FileError(concat(where, ": an .npz holds NAME.npy members only"));
    }
    if (st.size > (std::uint64_t{1} << 34)) throw core::LimitError(concat(where, ": member of ", st.size, " bytes is over 16 GiB"));
    std::string bytes(static_cast<std::size_t>(st.size), '\0');
    zip_file_t* file = zip_fopen_index(archive.get(), static_cast<zip_uint64_t>(e), 0);
    if (file == nullptr) throw core::FileError(concat(where, ": ", zip_strerror(archive.get())));
    const zip_int64_t got = zip_fread(file, bytes.data(), bytes.size());
    const std::string file_error = got < 0 ? zip_file_strerror(file) : "";
    zip_fclose(file);
    if (got < 0 || static_cast<std::uint64_t>(got) != st.size) {
      throw core::FileError(concat(where, ": damaged member (read ", got, " of ", st.size, " bytes) ", file_error));
    }
    arrays[member.substr(0, member.size() - 4)] = parse_npy(bytes, where);
  }
  return arrays;
}

void write_npz(const std::string& path, const std::map<std::string, NpyArray>& arrays) {
  // Built in memory, then written atomically like every other output.
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* buffer = zip_source_buffer_create(nullptr, 0, 0, &error);
  if (buffer == nullptr) throw std::runtime_error(concat("cannot write '", path, "': ", zip_error_strerror(&error)));
  zip_t* archive = zip_open_from_source(buffer, ZIP_TRUNCATE, &error);
  if (archive == nullptr) {
    zip_source_free(buffer);
    throw std::runtime_error(concat("cannot write '", path, "': ", zip_error_strerror(&error)));
  }
  zip_source_keep(buffer);
  std::vector<std::string> members;  // libzip reads them at zip_close
  members.reserve(arrays.size());
  bool ok = true;
  for (const auto& [name, array] : arrays) {
    members.push_back(npy_bytes(array));
    zip_source_t* src = zip_source_buffer(archive, members.back().data(), members.back().size(), 0);
    const zip_int64_t index = src ? zip_file_add(archive, (name + ".npy").c_str(), src, ZIP_FL_OVERWRITE) : -1;
    if (index < 0) {
      if (src) zip_source_free(src);
      ok = false;
      break;
    }
    zip_set_file_compression(archive, static_cast<zip_uint64_t>(index), ZIP_CM_STORE, 0);
  }
  if (!ok || zip_close(archive) != 0) {
    const std::string why = zip_strerror(archive);
    zip_discard(archive);
    zip_source_free(buffer);
    throw std::runtime_error(concat("cannot write '", path, "': ", why));
  }
  std::string bytes;
  zip_stat_t st;
  if (zip_source_stat(buffer, &st) == 0 && zip_source_open(buffer) == 0) {
    bytes.resize(static_cast<std::size_t>(st.size));
    const zip_int64_t got = zip_source_read(buffer, bytes.data(), bytes.size());
    zip_source_close(buffer);
    if (got < 0 || static_cast<std::size_t>(got) != bytes.size()) bytes.clear();
  }
  zip_source_free(buffer);
  if (bytes.empty()) throw std::runtime_error(concat("cannot write '", path, "': the zip archive could not be assembled"));
  write_file_atomically(path, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}
#else
bool npz_supported() { return false; }

namespace {
[[noreturn]] void no_libzip(const std::string& path) {
  throw core::InputError(concat(path, ": this build has no libzip, so .npz (AevaScenes) input and output are off; "
                                "install libzip-dev (scripts/setup.sh) and configure again"));
}
}  // namespace

std::map<std::string, NpyArray> read_npz(const std::string& path) { no_libzip(path); }
void write_npz(const std::string& path, const std::map<std::string, NpyArray>&) { no_libzip(path); }
#endif

}  // namespace fmcw::io
