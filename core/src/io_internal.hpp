#pragma once

// Helpers shared by the core file formats (map_io, marker_io, route_io): whole-file reads and
// writes, number formatting that round-trips, and typed access to yaml-cpp nodes that turns
// yaml-cpp's exceptions into absl::Status. Not part of the public API.

#include <yaml-cpp/yaml.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"
#include "fleetnav/core/echo_input.hpp"
#include "strings_internal.hpp"

namespace fleetnav::internal {

/// Reads a whole file; NotFound when it cannot be opened.
inline absl::StatusOr<std::string> ReadFileToString(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return absl::NotFoundError(absl::StrCat("cannot open ", path, ": ", std::strerror(errno)));
  }
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) return absl::DataLossError(absl::StrCat("error while reading ", path));
  return contents.str();
}

/// Writes (replaces) a whole file; FailedPrecondition when it cannot be written.
inline absl::Status WriteStringToFile(const std::string& path, std::string_view contents) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) {
    return absl::FailedPreconditionError(
        absl::StrCat("cannot write ", path, ": ", std::strerror(errno)));
  }
  out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
  out.close();
  if (!out) return absl::FailedPreconditionError(absl::StrCat("error while writing ", path));
  return absl::OkStatus();
}

/// The shortest decimal text that reads back to exactly `value`, in YAML spelling for
/// non-finite values (.nan, .inf, -.inf).
inline std::string FormatDouble(double value) {
  if (std::isnan(value)) return ".nan";
  if (std::isinf(value)) return value > 0 ? ".inf" : "-.inf";
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

/// A string as a YAML scalar, quoted only when it needs to be.
inline std::string YamlScalar(const std::string& text) {
  YAML::Emitter emitter;
  emitter << text;
  return emitter.c_str();
}

/// Parses YAML text into a node; InvalidArgument with yaml-cpp's message on a syntax error.
inline absl::StatusOr<YAML::Node> LoadYaml(std::string_view text, absl::string_view what) {
  try {
    return YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": YAML syntax error: ", e.what()));
  }
}

/// Short text of a node for error messages.
inline std::string NodeText(const YAML::Node& node) {
  try {
    if (node.IsScalar()) return node.Scalar();
    YAML::Emitter emitter;
    emitter << YAML::Flow << node;
    return emitter.c_str();
  } catch (const YAML::Exception&) {
    return "?";
  }
}

/// node as a double; InvalidArgument naming `field` when it is not a number.
inline absl::StatusOr<double> AsDouble(const YAML::Node& node, absl::string_view field) {
  if (!node.IsScalar()) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": expected a number"));
  }
  try {
    return node.as<double>();
  } catch (const YAML::Exception&) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": expected a number, got '", EchoInput(node.Scalar()), "'"));
  }
}

/// node as an int; InvalidArgument naming `field` when it is not an integer.
inline absl::StatusOr<int> AsInt(const YAML::Node& node, absl::string_view field) {
  if (!node.IsScalar()) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": expected an integer"));
  }
  try {
    return node.as<int>();
  } catch (const YAML::Exception&) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": expected an integer, got '", EchoInput(node.Scalar()), "'"));
  }
}

/// node as a string; InvalidArgument naming `field` when it is not a scalar.
inline absl::StatusOr<std::string> AsString(const YAML::Node& node, absl::string_view field) {
  if (!node.IsScalar()) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": expected a string"));
  }
  return node.Scalar();
}

/// The string keys of a map node, in file order; InvalidArgument for a non-scalar key.
inline absl::StatusOr<std::vector<std::string>> MapKeys(const YAML::Node& node,
                                                        absl::string_view field) {
  std::vector<std::string> keys;
  for (const auto& entry : node) {
    if (!entry.first.IsScalar()) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": keys must be plain names"));
    }
    keys.push_back(entry.first.Scalar());
  }
  return keys;
}

/// InvalidArgument naming the first key of the map `node` that is not in `allowed`.
inline absl::Status CheckKnownKeys(const YAML::Node& node,
                                   std::initializer_list<absl::string_view> allowed,
                                   absl::string_view field) {
  auto keys = MapKeys(node, field);
  if (!keys.ok()) return keys.status();
  for (const std::string& key : *keys) {
    bool known = false;
    for (absl::string_view name : allowed) known = known || key == name;
    if (!known) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": unknown key '", EchoInput(key), "'"));
    }
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::internal
