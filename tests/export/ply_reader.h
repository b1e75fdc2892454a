// A tiny binary little-endian PLY reader for the export tests: an independent check of what the writers wrote.
#pragma once

#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/files.h"

namespace cellform::test {

// The elements of a PLY, every value as a double (lists flattened).
struct PlyProperty {
  std::string type;        // scalar type, or the index type of a list
  std::string count_type;  // empty unless a list
  std::string name;
};
struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  std::vector<std::vector<double>> rows;  // every value, lists flattened without their count
};
struct Ply {
  std::string format;
  std::vector<std::string> comments;
  std::vector<PlyElement> elements;
};

inline std::size_t type_size(const std::string& t) {
  if (t == "uchar" || t == "char") return 1;
  if (t == "ushort" || t == "short") return 2;
  if (t == "uint" || t == "int" || t == "float") return 4;
  if (t == "double") return 8;
  FAIL("unknown PLY type " << t);
  return 0;
}

inline double read_value(const std::string& data, std::size_t& at, const std::string& t) {
  REQUIRE(at + type_size(t) <= data.size());
  const char* p = data.data() + at;
  at += type_size(t);
  if (t == "uchar") return static_cast<unsigned char>(*p);
  if (t == "uint") {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
  }
  if (t == "int") {
    std::int32_t v;
    std::memcpy(&v, p, 4);
    return v;
  }
  if (t == "float") {
    float v;
    std::memcpy(&v, p, 4);
    return v;
  }
  if (t == "double") {
    double v;
    std::memcpy(&v, p, 8);
    return v;
  }
  FAIL("type not used by cellform: " << t);
  return 0;
}

inline Ply parse_ply(const std::string& data) {
  Ply ply;
  const std::size_t end = data.find("end_header\n");
  REQUIRE(end != std::string::npos);
  std::istringstream header(data.substr(0, end));
  std::string line;
  std::getline(header, line);
  REQUIRE(line == "ply");
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "format") {
      std::getline(words >> std::ws, ply.format);
    } else if (key == "comment") {
      std::string rest;
      std::getline(words >> std::ws, rest);
      ply.comments.push_back(rest);
    } else if (key == "element") {
      PlyElement e;
      words >> e.name >> e.count;
      ply.elements.push_back(e);
    } else if (key == "property") {
      REQUIRE(!ply.elements.empty());
      PlyProperty p;
      words >> p.type;
      if (p.type == "list") words >> p.count_type >> p.type;
      words >> p.name;
      ply.elements.back().properties.push_back(p);
    } else {
      FAIL("unexpected header line: " << line);
    }
  }
  std::size_t at = end + std::strlen("end_header\n");
  for (PlyElement& e : ply.elements) {
    for (std::size_t r = 0; r < e.count; ++r) {
      std::vector<double> row;
      for (const PlyProperty& p : e.properties) {
        if (p.count_type.empty()) {
          row.push_back(read_value(data, at, p.type));
        } else {
          const auto n = static_cast<std::size_t>(read_value(data, at, p.count_type));
          for (std::size_t k = 0; k < n; ++k) row.push_back(read_value(data, at, p.type));
        }
      }
      e.rows.push_back(row);
    }
  }
  CHECK(at == data.size());  // nothing left over
  return ply;
}

inline std::vector<std::string> names(const PlyElement& e) {
  std::vector<std::string> out;
  for (const auto& p : e.properties) out.push_back(p.name);
  return out;
}

}  // namespace cellform::test
