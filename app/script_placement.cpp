// What a script reads and places, checked: the files it names (where they are), the cells its shapes place at one
// point, and mesh{} obstacles that cannot be what was meant (in other units than the cells).
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include "app/schema.h"
#include "app/script_placement.h"
#include "core/errors.h"

namespace cellform::app {

void scale_mesh(std::vector<Vec3>& vertices, double scale, const Vec3& offset, const std::string& file,
                const std::string& at) {
  for (Vec3& p : vertices) {
    p = p * scale + offset;
    if (!(p.cwiseAbs().maxCoeff() <= kFarthest))
      throw InvalidInput(
          at + "with scale = " + core::number_text(scale) +
          (offset.isZero() ? std::string() : " and offset " + core::point_text(offset.x(), offset.y(), offset.z())) +
          ", a vertex of '" + file + "' lies beyond " + core::number_text(kFarthest) +
          " model units, farther than any script position may");
  }
}

std::string file_message(const std::exception& e) {
  std::string m = core::error_text(e);
  if (m.rfind("mesh '", 0) == 0) m.erase(0, 5);
  return m;
}

std::filesystem::path script_file(const Impl& I, const std::string& given, const std::string& name,
                                  const std::string& at) {
  namespace fs = std::filesystem;
  const std::string folder = I.script_dir.empty() ? std::string(".") : I.script_dir.string();
  if (given.empty())
    throw InvalidInput(at + name + " is empty: give the file's path (a relative one is read from the script's " +
                       "folder, " + folder + ")");
  fs::path file = given;
  if (file.is_relative()) file = I.script_dir / file;
  std::error_code ec;
  // (a dangling link, or a folder that cannot be read: the reader says)
  if (fs::symlink_status(file, ec).type() != fs::file_type::not_found) return file;
  std::string m = at + name + ": '" + given + "' does not exist";
  if (given[0] == '~')
    m += " ('~' is not expanded in a script: give the whole path, or one from the script's folder, " + folder + ")";
  else if (fs::path(given).is_relative())
    m += " (read from the script's folder: " + file.string() + ")";
  auto lower = [](std::string t) {
    for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return t;
  };
  const std::string want = lower(file.filename().string());
  std::size_t looked = 0;  // (a folder of a million files is not read through for a hint)
  for (fs::directory_iterator it(file.parent_path().empty() ? fs::path(".") : file.parent_path(), ec), end;
       !ec && it != end && ++looked < 10000; it.increment(ec))
    if (lower(it->path().filename().string()) == want) {
      m += "; there is '" + it->path().filename().string() + "' (names are case-sensitive)";
      break;
    }
  throw InvalidInput(m);
}

// Refused beyond kMaxCoincident at one point: all of them are each other's nearest, so their neighbour search
// costs the square of their number (100,000 at one point took 97 s for 3 steps).
void check_coincident_cells(SceneConfig& cfg, const std::vector<std::size_t>& first,
                            const std::vector<std::string>& where) {
  constexpr std::size_t kMaxCoincident = 1000;
  const std::vector<InitialCell>& c = cfg.initial_cells;
  std::vector<std::size_t> order(c.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  // cells in one box of a thousandth of a rest length count as one point: 60,000 cells 1e-9 apart (a loop that
  // moves on by a rounding error) cost as many at one point do
  const double box = 1e-3 * cfg.scene.cells.rest_length;
  auto key = [&](std::size_t i) {
    const Vec3& p = c[i].position;
    return std::array<double, 3>{std::floor(p.x() / box), std::floor(p.y() / box), std::floor(p.z() / box)};
  };
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return std::pair(key(a), a) < std::pair(key(b), b); });
  std::size_t repeats = 0, group = 1, largest = 1, first_repeat = c.size(), at = 0;
  for (std::size_t k = 1; k < order.size(); ++k) {
    if (key(order[k]) != key(order[k - 1])) {
      group = 1;
      continue;
    }
    ++repeats;
    first_repeat = std::min(first_repeat, order[k]);  // (the earliest cell of a group is no repeat)
    if (++group > largest) {
      largest = group;
      at = order[k];
    }
  }
  if (repeats == 0) return;
  const auto shape = [&](std::size_t i) {
    return where[static_cast<std::size_t>(std::upper_bound(first.begin(), first.end(), i) - first.begin()) - 1];
  };
  const Vec3& p = c[at].position;
  if (largest > kMaxCoincident)
    throw InvalidInput(shape(at) + ": " + std::to_string(largest) + " cells lie at the point " +
                       core::point_text(p.x(), p.y(), p.z()) + " (rounded to a thousandth of a rest length), over " +
                       std::to_string(kMaxCoincident) +
                       ": each is every other's nearest, so their neighbour search takes the square of their number; "
                       "place them apart");
  cfg.notes.push_back(
      shape(first_repeat) + ": " + std::to_string(repeats) + (repeats == 1 ? " cell lies" : " cells lie") +
      " at the point of an earlier cell (rounded to a thousandth of a rest length; a shape placed twice?); "
      "coincident cells push apart in "
      "random directions");
}

void note_lost_meshes(SceneConfig& cfg) {
  const auto& meshes = cfg.scene.obstacles.meshes;
  if (meshes.empty()) return;
  const double rest = cfg.scene.cells.rest_length;
  Eigen::AlignedBox3d cells;
  for (const InitialCell& c : cfg.initial_cells) cells.extend(c.position);
  for (const forms::PetioleSpec& p : cfg.scene.petioles) cells.extend(p.at);
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    Eigen::AlignedBox3d box;
    for (const auto& t : meshes[k].triangles)
      for (const auto i : t) box.extend(meshes[k].vertices[i]);
    const std::string name =
        k < cfg.scene.obstacle_names.meshes.size() ? cfg.scene.obstacle_names.meshes[k] : "mesh " + std::to_string(k);
    const std::string file = k < cfg.mesh_files.size() ? " '" + cfg.mesh_files[k].first.string() + "'" : "";
    const double across = box.diagonal().norm();
    if (across < rest) {
      cfg.notes.push_back(
          name + ":" + file + " is " + core::number_text(across) +
          " model units across, less than a rest length (cells.rest_length = " + core::number_text(rest) +
          "): cells pass it by; is it drawn in other units than the cells (mesh.scale)?");
      continue;
    }
    if (cells.isEmpty()) continue;
    const double span = std::max(cells.diagonal().norm(), rest), gap = std::sqrt(box.squaredExteriorDistance(cells));
    if (gap > 5 * span)
      cfg.notes.push_back(
          name + ":" + file + " lies " + core::number_text(gap) +
          " model units from the cells placed at the start, which span " + core::number_text(span) + " (it spans " +
          core::number_text(across) +
          "): is it drawn in other units than the cells (mesh.scale), or away from them (mesh.offset)?");
  }
}

}  // namespace cellform::app
