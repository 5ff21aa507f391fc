// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_condyle_arcs_h
#define tkr_gait_condyle_arcs_h

#include <deal.II/base/point.h>

#include <string>
#include <vector>

namespace TKR::Gait
{
  /**
   * The distal arc of one femoral condyle in the sagittal (y, z) plane:
   * the circle the femur's lowest points follow as it flexes about the
   * arc's centre. The flexion axis of the gait should pass through it: a
   * condyle whose distal arc is centred elsewhere rises from or sinks into
   * the insert as the femur flexes.
   */
  struct DistalArc
  {
    /** The condyle's side: its mean x (mm). */
    double x = 0;
    /** The arc's centre (y, z) (mm) and radius (mm). */
    double centre_y = 0, centre_z = 0, radius = 0;
    /** Root mean square distance of the fitted points from the arc (mm). */
    double rms = 0;
    /** Points the fit used. */
    unsigned int n_points = 0;
  };

  /**
   * Each condyle's distal arc from the positions of the femur_contact nodes
   * at 0 deg flexion (the nodes on either side of the middle of their x
   * range are the two condyles), as scripts/mesh-implant estimates the
   * flexion axis (meshes/gen/flexion_axis.py, the same rule, so that the
   * run and the mesh report agree): the nodes within 1.5 mm in x of the
   * condyle's lowest node and within @p depth mm above it, their heights
   * freed of the condyle's frontal curvature (a parabola in x), and a
   * least-squares circle (Kasa's algebraic fit) through their (y, z).
   * A condyle with fewer than 5 such nodes gets no arc (n_points 0).
   */
  std::vector<DistalArc>
  distal_arcs(const std::vector<dealii::Point<3>> &points,
              const double                         depth = 2.);

  /**
   * A warning for the screen if the flexion axis through @p axis_point
   * (parallel to x) is more than @p limit mm from a condyle's distal-arc
   * centre, or if the two arcs' centres are more than @p limit apart (no
   * single axis is the centre of both): which condyle, by how much, and
   * what to do (doc/gait.md, "The flexion axis"). Empty if the axis is
   * within the limit of both. An arc fitted with an rms above 0.1 mm is
   * not judged (its profile is no circle: the window reaches into the
   * next arc or across a box).
   */
  std::string
  flexion_axis_warning(const std::vector<DistalArc> &arcs,
                       const dealii::Point<3>       &axis_point,
                       const double                  limit);
} // namespace TKR::Gait

#endif
