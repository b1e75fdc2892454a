// What a script reads and places, checked once it ran: the files it names (where they are, what units they are
// in) and the cells its shapes place.
#pragma once

#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "app/script_impl.h"

namespace cellform::app {

/// The file a script's parameter `name` ("mesh.file") names, `given`, relative to the script's folder. Throws
/// InvalidInput, `at` first, for an empty or missing one, saying where it was looked for (and a name in another case).
std::filesystem::path script_file(const Impl& I, const std::string& given, const std::string& name,
                                  const std::string& at);
/// A mesh reader's error without the word "mesh" it begins with, to follow "mesh.file: ".
std::string file_message(const std::exception& e);
/// Scales a mesh read from `file` (as the script names it) into model units and moves it by `offset` (model
/// units); refuses one that then lies beyond kFarthest, like every position a script gives.
void scale_mesh(std::vector<Vec3>& vertices, double scale, const Vec3& offset, const std::string& file,
                const std::string& at);
/// Cells placed at one point (the same box of a thousandth of a rest length) as an earlier one: a note naming the
/// first shape that did, refused beyond 1,000 there. `where[k]`: the shape call that placed cells from `first[k]`.
void check_coincident_cells(SceneConfig& cfg, const std::vector<std::size_t>& first,
                            const std::vector<std::string>& where);
/// Notes for a mesh{} obstacle less than a rest length across, or farther from the starting cells (box from box)
/// than five times their span: a file in other units than the cells, which mesh.scale converts?
void note_lost_meshes(SceneConfig& cfg);

}  // namespace cellform::app
