// Leaf blade outlines for space colonisation: parametric shapes, toothed margins, polygon files, checks.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace cellform::venation {

using Vec2 = Eigen::Vector2d;  ///< a point in the leaf plane, model units

/// A closed simple polygon, counter-clockwise, without a repeated end point (closure is implicit).
struct Outline {
  std::vector<Vec2> points;
};

/// Parametric blade shapes (Section 3.2 of Runions et al. 2005). All put the petiole (the attachment of
/// blade to petiole) at the origin and the tip on the +y axis.
enum class ShapeKind {
  ellipse,  ///< ellipse touching the petiole with its lower vertex
  ovate,    ///< egg shape, widest below the middle
  cordate,  ///< heart shape (cardioid): two basal lobes reach below the petiole
  lobed,    ///< ellipse with `lobes` indented lobes on each side (dissected)
  palmate,  ///< `lobes` lobes radiating from the petiole (digitate)
};

/// One triangular waveform summed into a toothed margin (Section 3.2): the margin moves outward by
/// amplitude * tri(count * u), u in [0, 1) the arc length fraction from the petiole, tri in [0, 1].
/// Near the petiole the teeth fade to nothing (as the fourth power of the distance), within four total amplitudes
/// (summed over the waves; at most a tenth of the leaf length) or, where a narrow cordate or palmate notch needs it,
/// the smallest of 1.5^k times that (up to half the length) which keeps the margin simple.
struct TriangularWave {
  double amplitude = 0.02;  ///< model units, outward along the margin normal (at growth scale 1)
  int count = 20;           ///< teeth along the whole margin (>= 1)
};

/// Parameters of make_outline(). Lengths are for growth scale 1.
struct ShapeParams {
  /// the blade's outline family
  ShapeKind kind = ShapeKind::ellipse;
  double length = 1.0;                ///< model units: petiole to tip
  double width = 0.6;                 ///< model units: widest extent across the leaf axis
  int lobes = 5;                      ///< lobed: lobes per side (>= 1); palmate: lobes in all (>= 2)
  double lobe_depth = 0.35;           ///< fraction of the radius cut between lobes, in [0, 1)
  std::vector<TriangularWave> teeth;  ///< empty = entire (smooth) margin
  int samples = 512;                  ///< vertices of the smooth outline before teeth (>= 16)
};

/// Samples a parametric outline. Throws core::InvalidInput naming "shape.<field>" for a bad parameter,
/// and "shape.teeth" if the teeth make the margin intersect itself.
Outline make_outline(const ShapeParams& params);

/// Parses an outline: one vertex "x y" per line, '#' starts a comment, blank lines are ignored. The
/// last vertex must repeat the first (the outline is closed explicitly). Either orientation is
/// accepted; the result is counter-clockwise. Throws core::InvalidInput naming `source` and the line
/// for malformed lines, and for an open, degenerate or self-intersecting outline.
Outline parse_outline(const std::string& text, const std::string& source);

/// parse_outline() of a file; core::FileError if it cannot be read.
Outline read_outline(const std::filesystem::path& path);

/// Twice-signed area / 2 (shoelace): positive for counter-clockwise outlines, model units squared.
double signed_area(const Outline& outline);

/// Where an outline's vertices came from in a file, for messages: the line of each vertex, and the power of
/// two the file's coordinates were divided by.
struct OutlineLines {
  std::vector<std::size_t> line;
  int exponent = 0;
};

/// Throws core::InvalidInput naming `what` unless the outline has >= 3 finite vertices, non-zero area
/// and no two non-adjacent edges touching or crossing. With `from`, vertices are named by their file lines
/// and coordinates given as the file has them.
void validate_outline(const Outline& outline, const std::string& what, const OutlineLines* from = nullptr);

/// Distance from `p` to the nearest point of the outline's boundary, model units.
double distance_to_boundary(const Outline& outline, const Vec2& p);

/// Fast point-in-polygon queries through horizontal bands of edges (even-odd rule). A grid over the
/// bounding box answers most queries at once: a cell that no edge comes within a cell of is wholly inside
/// or outside, as its centre is (the crossing test gives every point of such a cell the same answer, since
/// no edge lies near enough for rounding to matter); only points in the cells along the margin are tested
/// against the edges of their band.
class OutlineIndex {
 public:
  OutlineIndex() = default;
  /// `grid`: lay the grid (O(64 cells a vertex) to build; without it every query takes the crossing test).
  explicit OutlineIndex(const Outline& outline, bool grid = true);
  bool contains(const Vec2& p) const;
  /// Whether the grid was laid (it is not for a box too small for its coordinates' rounding, or beyond 1e+-140).
  bool has_grid() const { return !cell_class_.empty(); }
  /// contains() without the grid: the crossing test against the edges of the point's band.
  bool crossing_test(const Vec2& p) const;
  /// Whether the segment from `a` to `b` lies in the blade: `b` inside and no edge of the outline crossing
  /// it (a segment that only touches an edge or a vertex stays in, and so does one that starts on the outline,
  /// or outside it by up to 1e-6 of the outline's box diagonal, as validate(Leaf) allows a seed).
  /// For a vein segment from a node inside, which may not cut across a sinus or between teeth.
  bool segment_inside(const Vec2& a, const Vec2& b) const;
  double area() const { return area_; }
  const Vec2& lo() const { return lo_; }  ///< bounding box
  const Vec2& hi() const { return hi_; }
  const Outline& outline() const { return outline_; }

 private:
  Outline outline_;
  Vec2 lo_ = Vec2::Zero(), hi_ = Vec2::Zero();
  double area_ = 0, band_height_ = 1;
  std::vector<std::size_t> band_start_;
  std::vector<std::size_t> band_edges_;
  // the grid: gx_ x gy_ cells, row-major, 0 = outside, 1 = inside, 2 = near an edge (empty: no grid)
  long gx_ = 0, gy_ = 0;
  double inv_w_ = 0, inv_h_ = 0;
  std::vector<std::uint8_t> cell_class_;
};

}  // namespace cellform::venation
