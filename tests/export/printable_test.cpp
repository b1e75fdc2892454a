// Tests of export/printable.h: closed-form volumes and areas, topology of thickened vein graphs and shells,
// and the files checked by check_mesh, admesh and OpenSCAD.
#include "export/printable.h"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "core/errors.h"
#include "core/random.h"
#include "export/mesh_check.h"
#include "export/mesh_files.h"
#include "export/mesh_read.h"
#include "tests/export/ply_reader.h"
#include "tests/export/printable_fixtures.h"

using namespace cellform;
using core::Vec3;
using exporters::PrintableMesh;
using exporters::Segment;
using exporters::ThickenParams;
using exporters::ThickenReport;
namespace fs = std::filesystem;
using cellform::testing::exact;
using cellform::testing::require_printable;
using cellform::testing::Shell;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("cellform-printable-test-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Volume and area of a round cone (hull of spheres ra at 0 and rb at d on an axis), closed form:
// a frustum between the tangent circles plus the two outer spherical caps.
std::pair<double, double> round_cone(double d, double ra, double rb) {
  const double s = (ra - rb) / d, c = std::sqrt(1 - s * s);
  const double x1 = ra * s, x2 = d + rb * s, R1 = ra * c, R2 = rb * c, h = x2 - x1;
  const double ha = ra * (1 + s), hb = rb * (1 - s);  // cap heights
  const double volume = M_PI * h / 3 * (R1 * R1 + R1 * R2 + R2 * R2) + M_PI * ha * ha * (3 * ra - ha) / 3 +
                        M_PI * hb * hb * (3 * rb - hb) / 3;
  const double area = M_PI * (R1 + R2) * std::hypot(h, R1 - R2) + 2 * M_PI * ra * ha + 2 * M_PI * rb * hb;
  return {volume, area};
}

// The same volume by quadrature of the profile of revolution rho(x) = max of the two spheres' profiles
// and the straight flank between the tangent circles.
double round_cone_volume_numeric(double d, double ra, double rb) {
  const double s = (ra - rb) / d, c = std::sqrt(1 - s * s);
  const double x1 = ra * s, x2 = d + rb * s;
  const int n = 200000;
  const double a = -ra, b = d + rb, dx = (b - a) / n;
  double v = 0;
  for (int i = 0; i < n; ++i) {
    const double x = a + (i + 0.5) * dx;
    double rho = 0;
    if (std::abs(x) < ra) rho = std::max(rho, std::sqrt(ra * ra - x * x));
    if (std::abs(x - d) < rb) rho = std::max(rho, std::sqrt(rb * rb - (x - d) * (x - d)));
    if (x >= x1 && x <= x2) rho = std::max(rho, ra * c + (x - x1) / (x2 - x1) * (rb * c - ra * c));
    v += M_PI * rho * rho * dx;
  }
  return v;
}

std::vector<Segment> y_tree() {
  return {{{0, 0, 0}, {0, 10, 0}, 1.2, 0.9}, {{0, 10, 0}, {-5, 18, 1}, 0.9, 0.5}, {{0, 10, 0}, {5, 18, -1}, 0.9, 0.6}};
}

std::vector<Segment> square_loop() {
  const Vec3 c[4] = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  std::vector<Segment> s;
  for (int i = 0; i < 4; ++i) s.push_back({c[i], c[(i + 1) % 4], 1.0, 1.0});
  return s;
}

// A random branching tree of about n segments in a 60-unit cube (seeded).
std::vector<Segment> random_tree(std::size_t n, std::uint64_t seed) {
  core::Rng rng(seed);
  std::vector<Vec3> node{Vec3::Zero()};
  std::vector<Segment> s;
  while (s.size() < n) {
    const std::size_t parent =
        static_cast<std::size_t>(rng.uniform(0, 1) * static_cast<double>(node.size())) % node.size();
    const Vec3 dir(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    Vec3 p = node[parent] + 3 * dir;
    p = p.cwiseMax(Vec3::Constant(-30)).cwiseMin(Vec3::Constant(30));
    s.push_back({node[parent], p, rng.uniform(0.2, 0.8), rng.uniform(0.2, 0.8)});
    node.push_back(p);
  }
  return s;
}

bool have(const char* program) {
  return std::system((std::string("command -v ") + program + " >/dev/null 2>&1").c_str()) == 0;
}

std::string run(const std::string& command) {
  std::string out;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  REQUIRE(p);
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  ::pclose(p);
  return out;
}

// admesh's "Processing Statistics": every repair counter must be 0.
void require_admesh_clean(const fs::path& stl) {
  if (!have("admesh")) {
    WARN("admesh is not installed; skipping the admesh check");
    return;
  }
  const std::string out = run("admesh '" + stl.string() + "'");
  INFO(out);
  for (const char* counter :
       {"Degenerate facets", "Edges fixed", "Facets removed", "Facets added", "Facets reversed", "Backwards edges"}) {
    std::smatch m;
    REQUIRE(std::regex_search(out, m, std::regex(std::string(counter) + R"(\s*:\s*(\d+))")));
    CHECK(m[1] == "0");
  }
  std::smatch m;
  REQUIRE(std::regex_search(out, m, std::regex(R"(Total disconnected facets\s*:\s*(\d+))")));
  CHECK(m[1] == "0");
}

}  // namespace

TEST_CASE("a capsule's volume and area match the closed form within voxel error", "[printable]") {
  const double L = 10, r = 1, v = 0.05;
  ThickenReport rep;
  const auto m = exporters::thicken({{{0, 0, 0}, {L, 0, 0}, r, r}}, {}, exact(v), &rep);
  const auto check = require_printable(m);
  const double volume = M_PI * r * r * L + 4.0 / 3 * M_PI * r * r * r;
  const double area = 2 * M_PI * r * L + 4 * M_PI * r * r;
  CHECK(check.volume == Approx(volume).epsilon(0.01));
  CHECK(check.area == Approx(area).epsilon(0.01));
  CHECK(rep.volume == Approx(check.volume));
  CHECK(rep.parts == 1);
  CHECK(check.genus == std::vector<int>{0});
  CHECK(rep.scale == 1);
  CHECK(rep.voxel_size == v);
  CHECK(check.bbox_min.x() == Approx(-r).margin(v));
  CHECK(check.bbox_max.x() == Approx(L + r).margin(v));
}

TEST_CASE("a tapered capsule's volume matches the round cone", "[printable]") {
  const double d = 8, ra = 2, rb = 0.7;
  const auto [volume, area] = round_cone(d, ra, rb);
  REQUIRE(round_cone_volume_numeric(d, ra, rb) == Approx(volume).epsilon(1e-5));
  const auto m =
      exporters::thicken({{{1, 2, 3}, Vec3(1, 2, 3) + d * Vec3(1, 1, 0.5).normalized(), ra, rb}}, {}, exact(0.05));
  const auto check = require_printable(m);
  CHECK(check.volume == Approx(volume).epsilon(0.01));
  CHECK(check.area == Approx(area).epsilon(0.01));
}

TEST_CASE("zero-length segments are spheres and zero radii are raised to the minimum", "[printable]") {
  ThickenParams p = exact(0.05);
  p.min_radius = 1.0;
  ThickenReport rep;
  const auto m = exporters::thicken({{{0, 0, 0}, {0, 0, 0}, 0, 0}}, {}, p, &rep);
  const auto check = require_printable(m);
  CHECK(rep.raised_radii == 2);
  CHECK(check.volume == Approx(4.0 / 3 * M_PI).epsilon(0.01));
}

TEST_CASE("automatic scale makes the largest extent 120 mm", "[printable]") {
  ThickenParams p;
  p.voxel_size = 0.4;
  ThickenReport rep;
  const auto m = exporters::thicken(y_tree(), {}, p, &rep);
  const auto check = require_printable(m);
  // the ideal round members reach 120 mm; the mesh lies on chords of them, which cost up to about two voxels
  // at a thin tip or rim (here 0.64 mm at 0.4 mm voxels; print.size documents it), and never add
  const auto within = [&](const exporters::MeshReport& c) {
    const double extent = (c.bbox_max - c.bbox_min).maxCoeff();
    INFO("extent " << extent << " mm, voxel " << p.voxel_size << " mm");
    CHECK(extent <= 120 + 1e-3);
    CHECK(extent >= 120 - 2 * p.voxel_size);
  };
  within(check);
  CHECK(rep.scale > 1);

  // the size counts the form as printed: thin veins raised to min_radius, and the shell's thickness (they
  // were left out, so such prints came out up to a few mm larger than asked)
  std::vector<Segment> thin = y_tree();
  for (Segment& g : thin) g.ra = g.rb = 0.001;
  p.min_radius = 3;
  const auto raised = require_printable(exporters::thicken(thin, {}, p, &rep));
  within(raised);
  p.min_radius = 0.4;
  p.shell_thickness = 4;
  const std::vector<std::array<Vec3, 3>> sheet = {{Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 5, 0)}};
  const auto slab = require_printable(exporters::thicken({}, sheet, p, &rep));
  within(slab);
}

TEST_CASE("a Y-shaped vein tree is one watertight part of genus 0", "[printable]") {
  ThickenReport rep;
  const auto m = exporters::thicken(y_tree(), {}, exact(0.1), &rep);
  const auto check = require_printable(m);
  CHECK(check.parts == 1);
  CHECK(check.genus == std::vector<int>{0});
  CHECK(rep.parts == 1);
}

TEST_CASE("a closed square vein loop has genus 1", "[printable]") {
  ThickenParams p = exact(0.1);
  p.adaptivity = 0.3;
  const auto m = exporters::thicken(square_loop(), {}, p);
  const auto check = require_printable(m);
  CHECK(check.parts == 1);
  CHECK(check.genus == std::vector<int>{1});
}

TEST_CASE("thickened meshes pass check_mesh, admesh and OpenSCAD, and survive the file round trip",
          "[printable][files]") {
  const fs::path dir = temp_dir("files");
  ThickenParams p;  // defaults: auto scale to 120 mm, auto voxel
  p.adaptivity = 0.2;
  ThickenReport rep;
  const auto m = exporters::thicken(square_loop(), {}, p, &rep);
  const auto check = require_printable(m);
  CHECK(check.genus == std::vector<int>{1});
  for (const char* name : {"loop.stl", "loop.obj", "loop.ply"}) {
    INFO(name);
    exporters::write_mesh(dir / name, m);
    const auto back = exporters::read_mesh(dir / name);
    CHECK(back.triangles.size() == m.triangles.size());
    CHECK(back.vertices.size() == m.vertices.size());
    const auto r = require_printable(back);
    CHECK(r.volume == Approx(check.volume).epsilon(1e-5));
    CHECK(r.genus == check.genus);
  }
  require_admesh_clean(dir / "loop.stl");
  exporters::MeshFileNotes notes;  // every STL facet's stored normal agrees with its corners' winding
  exporters::read_mesh(dir / "loop.stl", notes);
  CHECK(notes.stored_normals == m.triangles.size());
  CHECK(notes.normals_against_winding == 0);
  exporters::write_scad(dir / "loop.scad", m);
  {  // OpenSCAD wants faces clockwise seen from outside: each triangle written (t0, t2, t1)
    const std::string scad = test::slurp(dir / "loop.scad");
    std::istringstream faces(scad.substr(scad.find("faces = [")));
    faces.ignore(9);
    std::size_t k = 0, bad = 0;
    char c1 = 0, c2 = 0, c3 = 0, c4 = 0;
    long a = 0, b = 0, c = 0;
    while (faces >> c1 >> a >> c2 >> b >> c3 >> c >> c4 && c1 == '[') {
      bad += k >= m.triangles.size() || a != m.triangles[k][0] || b != m.triangles[k][2] || c != m.triangles[k][1];
      ++k;
      faces >> c1;  // ',' or the closing ']'
    }
    CHECK(k == m.triangles.size());
    CHECK(bad == 0);
  }

  if (!have("openscad")) {
    WARN("openscad is not installed; skipping the OpenSCAD checks");
  } else {
    // the polyhedron renders with positive volume (faces clockwise seen from outside)
    const std::string out =
        run("openscad -o '" + (dir / "from_scad.stl").string() + "' '" + (dir / "loop.scad").string() + "'");
    INFO(out);
    REQUIRE(fs::exists(dir / "from_scad.stl"));
    const auto rendered = exporters::read_mesh(dir / "from_scad.stl");
    const auto rr = exporters::check_mesh(rendered);
    CHECK(rr.volume == Approx(check.volume).epsilon(1e-3));
    CHECK(rr.closed_manifold());
    // and it imports our STL
    { std::ofstream(dir / "import.scad") << "import(\"" << (dir / "loop.stl").string() << "\");\n"; }
    const std::string out2 =
        run("openscad -o '" + (dir / "imported.stl").string() + "' '" + (dir / "import.scad").string() + "'");
    INFO(out2);
    REQUIRE(fs::exists(dir / "imported.stl"));
    CHECK(exporters::check_mesh(exporters::read_mesh(dir / "imported.stl")).volume ==
          Approx(check.volume).epsilon(1e-3));
  }
  fs::remove_all(dir);
}

TEST_CASE("write_vdb writes the level set", "[printable][files]") {
  const fs::path dir = temp_dir("vdb");
  const auto ls = exporters::voxelise(y_tree(), {}, exact(0.1));
  CHECK(ls.active_voxels() > 1000);
  exporters::write_vdb(dir / "tree.vdb", ls);
  REQUIRE(fs::exists(dir / "tree.vdb"));
  CHECK(fs::file_size(dir / "tree.vdb") > 1000);
  // OpenVDB reads it back, with every active voxel
  openvdb::initialize();
  openvdb::io::File file((dir / "tree.vdb").string());
  file.open();
  const openvdb::GridPtrVecPtr grids = file.getGrids();
  file.close();
  REQUIRE(grids->size() == 1);
  CHECK((*grids)[0]->activeVoxelCount() == ls.active_voxels());
  // a level set named as Houdini's VDB from Polygons and Blender's Mesh to Volume name theirs
  CHECK((*grids)[0]->getName() == "surface");
  CHECK((*grids)[0]->getGridClass() == openvdb::GRID_LEVEL_SET);
  // the same level set gives the same bytes (OpenVDB's random file UUID is replaced by one from the content)
  exporters::write_vdb(dir / "again.vdb", ls);
  std::ifstream a(dir / "tree.vdb", std::ios::binary), b(dir / "again.vdb", std::ios::binary);
  const std::string sa((std::istreambuf_iterator<char>(a)), {}), sb((std::istreambuf_iterator<char>(b)), {});
  CHECK(sa == sb);
  CHECK(
      std::regex_match(sa.substr(21, 36), std::regex("[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}")));
  CHECK_THROWS_AS(exporters::write_vdb(dir / "no" / "such" / "dir.vdb", ls), core::FileError);
  // an empty handle is refused, not read through a null pointer (review), and leaves no file
  CHECK_THROWS_AS(exporters::write_vdb(dir / "empty.vdb", exporters::LevelSet()), core::InvalidInput);
  CHECK_FALSE(fs::exists(dir / "empty.vdb"));
  CHECK_THROWS_AS(exporters::mesh_level_set(exporters::LevelSet(), exact(0.1)), core::InvalidInput);
  fs::remove_all(dir);
}

TEST_CASE("bad input is refused with a message a user can act on", "[printable]") {
  CHECK_THROWS_AS(exporters::thicken({}, {}, ThickenParams{}), core::InvalidInput);
  auto nan = y_tree();
  nan[1].b.y() = std::nan("");
  CHECK_THROWS_WITH(exporters::thicken(nan, {}, ThickenParams{}), Catch::Contains("segment 1"));
  auto negative = y_tree();
  negative[2].ra = -1;
  CHECK_THROWS_AS(exporters::thicken(negative, {}, ThickenParams{}), core::InvalidInput);
  ThickenParams coarse;
  coarse.voxel_size = 1;  // coarser than min_radius 0.4
  CHECK_THROWS_WITH(exporters::thicken(y_tree(), {}, coarse), Catch::Contains("min_radius"));
  // a scale that makes the veins span no more than the thinnest vein is thick: a 0.8 mm ball was printed
  // for a leaf at print.scale = 1e-9 (audit, December 2026), while print.size = 0.001 was refused
  ThickenParams tiny;
  tiny.scale = 1e-9;
  CHECK_THROWS_WITH(exporters::thicken(y_tree(), {}, tiny), Catch::Contains("the veins would be larger than the form"));
  tiny.scale = 0.7 / 18;  // the tree spans 18 units along y: 0.7 mm, less than a vein is thick (0.8)
  CHECK_THROWS_WITH(exporters::thicken(y_tree(), {}, tiny), Catch::Contains("use a larger scale"));
  // with a sheet printed too, the sheet is the form (review: a sheet with its first vein cells was refused)
  const std::vector<std::array<Vec3, 3>> sheet{{Vec3(-100, -100, 0), Vec3(100, -100, 0), Vec3(0, 100, 0)}};
  CHECK_NOTHROW(exporters::thicken(y_tree(), sheet, tiny));
  // a small form far from the origin: the voxels are counted from there, and the message says so (review)
  const std::vector<Segment> far{{{1e6, 1e6, 0}, {1e6 + 1, 1e6, 0}, 0.1, 0.1}};
  CHECK_THROWS_WITH(exporters::thicken(far, {}, exact(0.1)), Catch::Contains("move it nearer the origin"));
}

TEST_CASE("the memory estimate refuses and suggests a voxel size that fits", "[printable]") {
  ThickenParams p = exact(0.05);
  p.max_memory_bytes = 1e6;
  const std::vector<Segment> capsule{{{0, 0, 0}, {10, 0, 0}, 1, 1}};
  auto refusal = [&] {
    try {
      exporters::thicken(capsule, {}, p);
    } catch (const core::InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // a limit below what the segments alone take: no voxel helps, and none is named
  p.max_memory_bytes = 100;
  const std::string none = refusal();
  INFO(none);
  CHECK_THAT(none, Catch::Contains("1 vein segments and sheet triangles alone need about") &&
                       Catch::Contains("no voxel size fits: raise the memory limit") && !Catch::Contains("would be"));
  p.max_memory_bytes = 1e6;
  // a voxel of 0.05 mm given, min_radius 0.05 mm, but the vein is 1 mm thick: the automatic voxel could go
  // up to 1 mm (audit: a 2 m canopy of veins 6 mm thick was refused as if they would vanish)
  const std::string given = refusal();
  INFO(given);
  CHECK_THAT(given, Catch::Contains("use the automatic voxel size (0), which may be as coarse as the thinnest "
                                    "member, 1 mm") &&
                        !Catch::Contains("vanish"));
  p.voxel_size = 0;
  CHECK_NOTHROW(exporters::thicken(capsule, {}, p));  // raised (to 1 mm at most)
  p.voxel_size = 0.05;
  // with a vein of 0.01 mm raised to min_radius 0.05 mm no voxel that fits keeps it: none is advised
  const std::vector<Segment> thread{{{0, 0, 0}, {400, 0, 0}, 0.01, 0.01}};
  std::string thin;
  try {
    exporters::thicken(thread, {}, p);
  } catch (const core::InvalidInput& e) {
    thin = e.what();
  }
  INFO(thin);
  CHECK_THAT(thin, Catch::Contains("smaller scale") && Catch::Contains("above min_radius") &&
                       Catch::Contains("a larger min_radius allows a coarser voxel") && !Catch::Contains("at least"));
  p.min_radius = 1;  // veins of 1 mm allow a coarser voxel
  const std::string message = refusal();
  INFO(message);
  std::smatch m;
  REQUIRE(std::regex_search(message, m, std::regex(R"(voxel size of at least ([0-9.eE+-]+) mm)")));
  const double suggested = std::stod(m[1]);
  CHECK(suggested > p.voxel_size);
  CHECK(suggested <= p.min_radius);
  // a voxel so small that the estimate overflows gets the same advice, not "inf"
  const double fits = suggested;
  p.voxel_size = 1e-300;
  const std::string tiny = refusal();
  INFO(tiny);
  CHECK_THAT(tiny, Catch::Contains("more memory than the limit") && !Catch::Contains("inf"));
  REQUIRE(std::regex_search(tiny, m, std::regex(R"(voxel size of at least ([0-9.eE+-]+) mm)")));
  CHECK(std::stod(m[1]) == Approx(fits).epsilon(0.01));
  p.voxel_size = suggested;
  ThickenReport rep;
  CHECK_NOTHROW(exporters::thicken(capsule, {}, p, &rep));
  CHECK(rep.estimated_bytes <= p.max_memory_bytes);
}

TEST_CASE("the automatic voxel size gives way to the memory limit, up to min_radius", "[printable]") {
  ThickenParams p = exact(0.05);
  p.voxel_size = 0;  // auto: min_radius / 2
  p.min_radius = 1;
  const std::vector<Segment> capsule{{{0, 0, 0}, {10, 0, 0}, 1, 1}};
  ThickenReport free_rep;
  exporters::thicken(capsule, {}, p, &free_rep);  // the default limit holds it at 0.5 mm
  CHECK(free_rep.voxel_size == 0.5);
  CHECK(free_rep.voxel_raised_from == 0);
  // a limit between the estimates at 0.5 mm and at min_radius: the voxel is raised just enough
  p.max_memory_bytes = free_rep.estimated_bytes / 2;
  ThickenReport rep;
  const auto m = exporters::thicken(capsule, {}, p, &rep);
  CHECK(rep.voxel_raised_from == 0.5);
  CHECK(rep.voxel_size > 0.5);
  CHECK(rep.voxel_size <= p.min_radius);
  CHECK(rep.estimated_bytes <= p.max_memory_bytes);
  CHECK(rep.voxel_size == Approx(0.5 * std::sqrt(2.0)).epsilon(0.15));  // the estimate goes as voxel^-2 here
  CHECK(rep.voxel_size * 100 == Approx(std::round(rep.voxel_size * 100)).margin(1e-9));  // two digits: 0.xy mm
  CHECK(m.triangles.size() > 0);
  // the same voxel given explicitly gives the same solid
  ThickenParams given = p;
  given.voxel_size = rep.voxel_size;
  CHECK(exporters::thicken(capsule, {}, given).triangles == m.triangles);
  // a limit just above what min_radius needs: allowed (5% headroom on the fit must not push it past)
  ThickenParams at_min = p;
  at_min.voxel_size = p.min_radius;
  at_min.max_memory_bytes = 1e12;
  ThickenReport min_rep;
  exporters::thicken(capsule, {}, at_min, &min_rep);
  for (const double above : {1.0, 1.02, 1.04}) {
    INFO(above);
    p.max_memory_bytes = min_rep.estimated_bytes * above;
    ThickenReport near;
    REQUIRE_NOTHROW(exporters::thicken(capsule, {}, p, &near));
    CHECK(near.voxel_size <= p.min_radius);
    CHECK(near.estimated_bytes <= p.max_memory_bytes);
  }
  // where even min_radius does not fit, the refusal stays, and an explicit voxel is never changed
  p.max_memory_bytes = min_rep.estimated_bytes * 0.99;
  CHECK_THROWS_WITH(exporters::thicken(capsule, {}, p), Catch::Contains("raise the memory limit"));
  p.max_memory_bytes = 1e3;
  CHECK_THROWS_WITH(exporters::thicken(capsule, {}, p), Catch::Contains("raise the memory limit"));
  given.voxel_size = 0.5;
  given.max_memory_bytes = free_rep.estimated_bytes / 2;
  CHECK_THROWS_WITH(exporters::thicken(capsule, {}, given), Catch::Contains("use a voxel size of at least"));
}

TEST_CASE("a thickened mesh keeps no micrometre edge, and stays printable", "[printable]") {
  // where two voxels' vertices meet at their shared corner the mesher leaves edges of a few micrometres,
  // and slivers that repair tools flag; they are collapsed (here 0.44% of the mesher's edges were under a
  // twentieth of a voxel; about 1 in 100 of them stays: those whose collapse would leave a vertex of two
  // triangles)
  const Shell shell{{Vec3(-30, -30, 0), Vec3(30, -30, 0), Vec3(0, 30, 0)}};
  ThickenParams p;
  p.voxel_size = 0.3;
  ThickenReport rep;
  const auto m = exporters::thicken(random_tree(800, 11), shell, p, &rep);
  require_printable(m);
  std::size_t short_sides = 0;  // triangle sides: each edge of the closed mesh twice
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) short_sides += (m.vertices[t[k]] - m.vertices[t[(k + 1) % 3]]).norm() < 0.05 * 0.3;
  CHECK(short_sides * 2000 < 3 * m.triangles.size());  // under 0.05%
}

TEST_CASE("thickening is bitwise identical with 1 and 2 threads", "[printable]") {
  const auto tree = random_tree(800, 11);
  const Shell shell{{Vec3(-30, -30, 0), Vec3(30, -30, 0), Vec3(0, 30, 0)}};
  ThickenParams p;
  p.voxel_size = 0.3;
  p.threads = 1;
  const auto a = exporters::thicken(tree, shell, p);
  p.threads = 2;
  const auto b = exporters::thicken(tree, shell, p);
  REQUIRE(a.vertices.size() == b.vertices.size());
  REQUIRE(a.triangles.size() == b.triangles.size());
  CHECK(a.triangles == b.triangles);
  bool same = true;
  for (std::size_t i = 0; i < a.vertices.size(); ++i) same = same && a.vertices[i] == b.vertices[i];
  CHECK(same);
  require_printable(a);
}

TEST_CASE("the progress callback sees each stage advance to 1 and can cancel it", "[printable]") {
  const auto tree = random_tree(800, 11);
  ThickenParams p;
  p.voxel_size = 0.3;
  const auto plain = exporters::thicken(tree, {}, p);

  std::vector<double> seen;
  p.progress = [&](double f) {
    seen.push_back(f);
    return true;
  };
  ThickenReport rep;
  const exporters::LevelSet ls = exporters::voxelise(tree, {}, p, &rep);
  const std::vector<double> voxel_stage = seen;
  seen.clear();
  const auto watched = exporters::mesh_level_set(ls, p, &rep);
  const std::vector<double> mesh_stage = seen;
  for (const auto* stage : {&voxel_stage, &mesh_stage}) {
    REQUIRE(stage->size() >= 2);
    CHECK(stage->front() == 0.0);
    CHECK(stage->back() == 1.0);
    CHECK(std::is_sorted(stage->begin(), stage->end()));
  }
  CHECK(voxel_stage.size() >= 3);  // at least one block boundary inside the leaf loop
  // watching does not change the result
  CHECK(watched.triangles == plain.triangles);
  CHECK(watched.vertices == plain.vertices);

  // stopping after the first call in either stage throws Cancelled
  for (int stop_at : {1, 2}) {
    int calls = 0;
    p.progress = [&](double) { return ++calls < stop_at; };
    CHECK_THROWS_AS(exporters::voxelise(tree, {}, p), core::Cancelled);
    calls = 0;
    CHECK_THROWS_AS(exporters::mesh_level_set(ls, p), core::Cancelled);
  }
}

TEST_CASE("the plan is told before any voxel is made, as the report gives it", "[printable]") {
  ThickenParams p = exact(0.05);
  std::vector<std::string> events;
  exporters::ThickenReport planned;
  p.planned = [&](const exporters::ThickenReport& r) {
    events.push_back("planned");
    planned = r;
  };
  p.progress = [&](double) {
    events.push_back("progress");
    return true;
  };
  exporters::ThickenReport rep;
  exporters::thicken({{{0, 0, 0}, {10, 0, 0}, 1, 1}}, {}, p, &rep);
  REQUIRE(events.size() > 1);
  CHECK(events.front() == "planned");
  CHECK(std::count(events.begin(), events.end(), "planned") == 1);
  CHECK(planned.voxel_size == rep.voxel_size);
  CHECK(planned.segments == 1);
  CHECK(planned.height == rep.height);
  CHECK(planned.estimated_bytes == rep.estimated_bytes);
  // told without a report asked for, too
  int told = 0;
  p.planned = [&](const exporters::ThickenReport& r) { told += r.voxel_size == rep.voxel_size; };
  exporters::thicken({{{0, 0, 0}, {10, 0, 0}, 1, 1}}, {}, p);
  CHECK(told == 1);
}

TEST_CASE("lay_flat rests a flat form's thick and thin veins on one plane", "[printable]") {
  // two parallel veins in z = 0, radii 1 and 0.4 mm: centred, the thin one's underside is 0.6 mm above the thick
  // one's; laid flat, both rest on z = 0
  const std::vector<exporters::Segment> veins = {{{0, 0, 0}, {10, 0, 0}, 1, 1}, {{0, 5, 0}, {10, 5, 0}, 0.4, 0.4}};
  for (const bool flat : {false, true}) {
    CAPTURE(flat);
    ThickenParams p = exact(0.05);
    p.lay_flat = flat;
    p.min_radius = 0.3;
    ThickenReport rep;
    const auto m = exporters::thicken(veins, {}, p, &rep);
    require_printable(m);
    double thick = 1e9, thin = 1e9;
    for (const Vec3& v : m.vertices) (v.y() < 2.5 ? thick : thin) = std::min(v.y() < 2.5 ? thick : thin, v.z());
    CHECK(thick == Approx(flat ? 0 : -1).margin(0.05));
    CHECK(thin == Approx(flat ? 0 : -0.4).margin(0.05));
    CHECK(rep.parts == 2);
  }
  // by its radius as printed: raised to min_radius = 0.6 mm, the thin vein rests on the bed too, and the form is
  // the thick vein's 2 mm high
  ThickenParams p = exact(0.05);
  p.lay_flat = true;
  p.min_radius = 0.6;
  ThickenReport rep;
  const auto m = exporters::thicken(veins, {}, p, &rep);
  double thin = 1e9;
  for (const Vec3& v : m.vertices)
    if (v.y() > 2.5) thin = std::min(thin, v.z());
  CHECK(thin == Approx(0).margin(0.05));
  CHECK(rep.height == Approx(2).margin(0.1));
}
