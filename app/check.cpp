// The check command over exporters::check_mesh.
#include "app/check.h"

#include <nlohmann/json.hpp>

#include "app/run.h"
#include "core/errors.h"
#include "export/mesh_check.h"

namespace cellform::app {

int check_command(const std::filesystem::path& file, bool json, std::ostream& out, std::ostream& err) {
  exporters::MeshReport r;
  try {
    r = exporters::check_mesh(exporters::read_mesh(file));
  } catch (const std::exception& e) {
    err << "cellform: " << e.what() << "\n";
    return usage;
  }
  if (json) {
    nlohmann::json j = {{"file", file.string()},
                        {"printable", r.printable()},
                        {"triangles", r.triangles},
                        {"vertices", r.vertices},
                        {"parts", r.parts},
                        {"boundary_edges", r.boundary_edges},
                        {"nonmanifold_edges", r.nonmanifold_edges},
                        {"nonmanifold_vertices", r.nonmanifold_vertices},
                        {"consistently_oriented", r.consistently_oriented},
                        {"self_intersections", r.self_intersections},
                        {"degenerate_triangles", r.degenerate_triangles},
                        {"volume_mm3", r.volume},
                        {"area_mm2", r.area},
                        {"bbox_min_mm", {r.bbox_min.x(), r.bbox_min.y(), r.bbox_min.z()}},
                        {"bbox_max_mm", {r.bbox_max.x(), r.bbox_max.y(), r.bbox_max.z()}},
                        {"genus", r.genus}};
    out << j.dump(2) << "\n";
  } else {
    out << file.string() << ": " << (r.printable() ? "printable" : "NOT printable") << "\n" << r.summary();
  }
  return r.printable() ? ok : failure;
}

}  // namespace cellform::app
