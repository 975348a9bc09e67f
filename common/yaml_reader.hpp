// Typed reading and atomic writing of world files (courses, corridors: OpenCV-FileStorage-style
// YAML, or JSON read as YAML) with yaml-cpp: every problem is thrown as an
// `Error` (constructed from a std::string) whose message names the source
// file, the key path (e.g. "tapes[2].gaps[0]") and what is wrong. Include only
// from a target that links yaml-cpp.
#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <system_error>

namespace ceilnav {

// "source: key: what" (no key: "source: what").
template <class Error>
[[noreturn]] void yaml_fail(const std::string& source, const std::string& key,
                            const std::string& what) {
  throw Error(source + ": " + (key.empty() ? std::string() : key + ": ") + what);
}

// "key[i]": the key path of a sequence element.
inline std::string yaml_at(const std::string& key, std::size_t i) {
  return key + "[" + std::to_string(i) + "]";
}

// The shortest text that reads back as the same double (for writers).
inline std::string yaml_number_text(double v) {
  std::array<char, 32> buf{};
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return {buf.data(), res.ptr};
}

// Writes `text` to "<path>.tmp" and renames it to `path`, so a failure
// leaves no partial file; throws Error naming the path.
template <class Error>
void write_world_file(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::out | std::ios::trunc);
    if (!out) throw Error(path + ": cannot open for writing: " + std::strerror(errno));
    out << text;
    out.flush();
    if (!out) {
      out.close();
      std::error_code ignored;
      std::filesystem::remove(tmp, ignored);
      throw Error(path + ": writing failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw Error(path + ": cannot rename the temporary file: " + ec.message());
  }
}

// The whole text of `path`; throws Error "path: cannot open: why".
template <class Error>
std::string read_world_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open: " + std::strerror(errno));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return text;
}

template <class Error>
struct YamlReader {
  std::string source;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    yaml_fail<Error>(source, key, what);
  }

  // `map` is a map whose keys are all `allowed` and hold every `required`.
  void keys(const YAML::Node& map, const std::string& key,
            std::initializer_list<const char*> allowed,
            std::initializer_list<const char*> required) const {
    if (!map.IsMap()) fail(key, "must be a map");
    for (const auto& kv : map) {
      const std::string name = kv.first.IsScalar() ? kv.first.Scalar() : std::string("?");
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return name == a; })) {
        fail(key.empty() ? name : key + "." + name, "unknown key");
      }
    }
    for (const char* r : required) {
      if (!map[r]) fail(key.empty() ? r : key + "." + r, "missing");
    }
  }

  double number(const YAML::Node& node, const std::string& key) const {
    if (!node || !node.IsScalar()) fail(key, "must be a number");
    double value = 0.0;
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(key, "'" + node.Scalar() + "' is not a number");
    }
    if (!std::isfinite(value)) fail(key, "must be finite");
    return value;
  }

  int integer(const YAML::Node& node, const std::string& key) const {
    if (!node || !node.IsScalar()) fail(key, "must be an integer");
    try {
      return node.as<int>();
    } catch (const YAML::Exception&) {
      fail(key, "'" + node.Scalar() + "' is not an integer");
    }
  }

  std::string text(const YAML::Node& node, const std::string& key) const {
    if (!node || !node.IsScalar()) fail(key, "must be a string");
    return node.Scalar();
  }

  // The root of a world file: `source_text` parsed (YAML, or JSON read as YAML), a
  // map whose keys are `allowed` and hold `required` (format and version
  // among them), `format` equal to `format_name` and `version` 1.
  YAML::Node world_root(const std::string& source_text, const char* format_name,
                        std::initializer_list<const char*> allowed,
                        std::initializer_list<const char*> required) const {
    YAML::Node root;
    try {
      root = YAML::Load(source_text);
    } catch (const YAML::Exception& e) {
      fail("", std::string("not YAML or JSON: ") + e.what());
    }
    if (!root.IsMap()) fail("", "top level is not a map of keys");
    keys(root, "", allowed, required);
    if (text(root["format"], "format") != format_name) {
      fail("format", std::string("must be '") + format_name + "'");
    }
    if (integer(root["version"], "version") != 1) fail("version", "must be 1");
    return root;
  }

  YAML::Node sequence(const YAML::Node& node, const std::string& key) const {
    if (!node.IsSequence()) fail(key, "must be a sequence");
    return node;
  }
};

}  // namespace ceilnav
