// Initial shapes: point sets the first cells are placed on.
#pragma once

#include <vector>

#include "core/types.h"

namespace cellform::forms {

using core::Vec3;

/// Points of a hexagonal lattice with spacing `spacing` (model units) inside a disc of `radius`
/// around `centre`, in the plane with unit normal `normal`. Always contains the centre.
/// Every shape throws core::InvalidInput for a size or spacing that is not a finite number > 0, and for
/// one that would need more than 50 million cells (the message names the sizes and the spacing).
std::vector<Vec3> hex_disc(const Vec3& centre, const Vec3& normal, double radius, double spacing);

/// Points of a hexagonal lattice filling a `width` x `height` rectangle centred at `centre` in the
/// plane with normal `normal` (width along the plane's first axis).
std::vector<Vec3> hex_rectangle(const Vec3& centre, const Vec3& normal, double width, double height, double spacing);

/// About evenly spaced points on a sphere (Fibonacci lattice), `spacing` model units apart.
std::vector<Vec3> sphere_points(const Vec3& centre, double radius, double spacing);

/// Points from `from` to `to` inclusive, at most `spacing` apart.
std::vector<Vec3> line_points(const Vec3& from, const Vec3& to, double spacing);

/// How many cells each shape above makes (the count their 50-million check uses), found without
/// building it, for a caller's own limit: exact for a rectangle, a sphere and a line (but for rounding at
/// the edges), within about the disc's rim for a disc. Meaningless (NaN, infinite or any number) for sizes
/// the shapes refuse.
double hex_disc_cells(double radius, double spacing);
double hex_rectangle_cells(double width, double height, double spacing);
double sphere_cells(double radius, double spacing);
double line_cells(const Vec3& from, const Vec3& to, double spacing);

/// Two unit vectors spanning the plane orthogonal to unit vector `normal`, chosen deterministically.
void plane_basis(const Vec3& normal, Vec3& u, Vec3& v);

}  // namespace cellform::forms
