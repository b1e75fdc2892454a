// Does a printed solid stand on the printer's bed by itself, and how much off its bottom would make it?
#pragma once

#include <cstddef>

#include "core/types.h"
#include "export/mesh.h"

namespace cellform::exporters {

/// The height of a printer's first layer (mm): what lies this close to the bed touches it.
inline constexpr double kFirstLayer = 0.2;

/// degrees: a solid that tips over at a smaller tilt of its bed hardly stands (cellform says so after a print)
inline constexpr double kSteadyTip = 5;
/// degrees: the cut off its bottom that cellform suggests gives a foot that tips only past this
inline constexpr double kFootTip = 10;

/// How a solid stands on the plane of its lowest point, upright as it is (lengths in the mesh's units, mm for
/// cellform's prints).
struct Stand {
  bool measured = false;  ///< false: no enclosed volume (an empty or open mesh, or one wound inward)
  double bed_z = 0;       ///< the lowest point's z
  /// area of what touches the bed: the convex hull, in plan, of the surface within `first_layer` of it (units^2)
  double footprint_area = 0;
  core::Vec3 centre_of_mass = core::Vec3::Zero();  ///< of the enclosed volume, of uniform density
  /// distance in plan from the centre of mass to the edge of the footprint: positive inside it (the solid
  /// stands), negative outside (it tips over)
  double margin = 0;
  /// degrees: the tilt of the bed that tips the solid over, atan(margin / height of the centre of mass above
  /// the bed) (negative: it does not stand); tan of it is the share of its weight a sideways push needs
  double tip_angle = 0;
  /// degrees: how far it turns from where it lies until it rests, rolling over the edge of what touches the bed
  /// (the hull of its vertices within first_layer of it) while its centre of mass lies beyond it, each turn
  /// until the next vertex meets the bed (quasi-static, at most 100 turns); when it stands, how far it rolls on
  /// after a tilt just past tip_angle.
  /// Under a few degrees it rocks onto more of its underside (a flat leaf whose lowest point is a thick vein)
  /// rather than falling over
  double settle_angle = 0;
};

/// Tips over at a tilt under kSteadyTip, or does not stand at all, and then turns kSteadyTip or more before
/// more of it meets the bed: falls, rather than rocks onto more of its underside.
inline bool falls(const Stand& s) { return s.measured && s.tip_angle < kSteadyTip && s.settle_angle >= kSteadyTip; }

/// Measures how `mesh`, a closed surface wound outward, stands on the plane z = its lowest z. Deterministic.
Stand stand_on_bed(const PrintableMesh& mesh, double first_layer = kFirstLayer);

/// The lowest cut off the bottom that leaves a solid which stands and tips only past `min_tip_angle` degrees,
/// among `heights` evenly spaced cuts up to `max_fraction` of the solid's height (the k-th at k / heights of
/// it): the part above each cut is measured exactly (its volume and centre of mass), standing on its cut face
/// (the convex hull of the section), and a cut that parts it into more pieces (a branch joined to the rest only
/// below the cut) does not count. 0 when none does. `threads`: 0 = all cores; the result does not depend
/// on it.
double base_cut_to_stand(const PrintableMesh& mesh, double min_tip_angle, double max_fraction = 0.5, int heights = 50,
                         int threads = 0);

}  // namespace cellform::exporters
