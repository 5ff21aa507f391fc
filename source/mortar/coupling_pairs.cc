// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// MortarCoupling: which slave and master faces couple (the R-tree search
// and the cheap rejections), lower bounds of the slave faces' distances to
// the master surface, and the coupling window built on them.

#include <deal.II/base/bounding_box.h>

#include <deal.II/numerics/rtree.h>

#include <tkr/mortar/mortar_coupling.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "coupling_data.h"

namespace TKR::Mortar
{
  using namespace dealii;

  namespace
  {
    /**
     * The master faces whose boxes meet the slave face's box stretched
     * along the plane normal @p n0 by the search distance (a master point
     * within that distance of the face along n0 lies in it), and by a
     * little tangentially for round-off.
     */
    void
    find_candidates(const RTree<BoxEntry>         &tree,
                    const std::array<Point<3>, 4> &slave_vertices,
                    const Tensor<1, 3>            &n0,
                    const double                   search_distance,
                    std::vector<BoxEntry>         &candidates)
    {
      candidates.clear();
      const BoundingBox<3> box     = face_box(slave_vertices);
      auto                 corners = box.get_boundary_points();
      const double         tangential =
        1e-3 * (box.side_length(0) + box.side_length(1) + box.side_length(2));
      for (unsigned int d = 0; d < 3; ++d)
        {
          const double margin = search_distance * std::abs(n0[d]) + tangential;
          corners.first[d] -= margin;
          corners.second[d] += margin;
        }
      tree.query(boost::geometry::index::intersects(BoundingBox<3>(corners)),
                 std::back_inserter(candidates));
    }

    /**
     * A lower bound of the height above @p plane of the points of the
     * master face @p face whose projections fall into @p box (infinity if
     * none does): the face is cut into n x n patches, each of them a
     * bilinear patch inside the convex hull of its corners (its points are
     * non-negative combinations of them), so that its heights lie between
     * its corners' and its projection inside their box. Much closer than
     * the smallest vertex height where the face is tilted against the
     * plane.
     */
    double
    lowest_height_over(const BilinearQuad   &face,
                       const AuxiliaryPlane &plane,
                       const BoundingBox<2> &box)
    {
      constexpr unsigned int                n = 4;
      std::array<Point2, (n + 1) * (n + 1)> x;
      std::array<double, (n + 1) * (n + 1)> beta;
      for (unsigned int j = 0; j <= n; ++j)
        for (unsigned int i = 0; i <= n; ++i)
          {
            const Point<3> p = face.point(Point2(double(i) / n, double(j) / n));
            x[j * (n + 1) + i]    = plane.coordinates(p);
            beta[j * (n + 1) + i] = plane.height(p);
          }
      const auto &[lower, upper] = box.get_boundary_points();
      double result              = std::numeric_limits<double>::infinity();
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int i = 0; i < n; ++i)
          {
            const unsigned int corners[4] = {j * (n + 1) + i,
                                             j * (n + 1) + i + 1,
                                             (j + 1) * (n + 1) + i,
                                             (j + 1) * (n + 1) + i + 1};
            bool               overlaps   = true;
            double             lowest     = beta[corners[0]];
            for (unsigned int d = 0; d < 2 && overlaps; ++d)
              {
                double min_x = x[corners[0]][d], max_x = min_x;
                for (const unsigned int c : corners)
                  {
                    min_x = std::min(min_x, x[c][d]);
                    max_x = std::max(max_x, x[c][d]);
                  }
                overlaps = max_x >= lower[d] && min_x <= upper[d];
              }
            if (!overlaps)
              continue;
            for (const unsigned int c : corners)
              lowest = std::min(lowest, beta[c]);
            result = std::min(result, lowest);
          }
      return result;
    }

  } // namespace

  // The candidates of the R-tree that face slave face e, lie within the
  // search distance along its plane normal and overlap its box in the
  // plane; the smallest distance bound among them.
  void
  MortarCoupling::find_pairs(const unsigned int           e,
                             const std::vector<Point<3>> &positions,
                             const MasterGeometry        &master_faces,
                             const double                 search_distance,
                             Accumulator                 &accumulator,
                             std::vector<FacePair>       &pairs)
  {
    const std::optional<SlaveProjection> &projection =
      slave_cache->projections[e];
    if (!projection)
      {
        ++stats.n_invalid_faces;
        return;
      }
    const auto &plane = projection->plane;
    find_candidates(master_faces.tree,
                    slave.face_vertices(e, positions),
                    plane.normal(),
                    search_distance,
                    accumulator.candidates);
    stats.n_candidate_pairs += accumulator.candidates.size();
    for (const auto &candidate : accumulator.candidates)
      {
        const unsigned int m = candidate.second;
        if (!(master_faces.normals[m] * plane.normal() < 0))
          continue; // not facing the slave face
        // The gap between the faces along n0 lies between these bounds
        // (each face lies between its vertices' heights).
        const MasterProjection master_plane(plane, master_faces.quads[m]);
        const double distance = master_plane.min_beta - projection->max_height;
        if (distance > search_distance ||
            master_plane.max_beta - projection->min_height < -search_distance)
          continue;
        const BoundingBox<2> master_box =
          BoundingBox<2>(master_plane.quad.vertices);
        if (projection->box.get_neighbor_type(master_box) ==
            NeighborType::not_neighbors)
          continue;
        pairs.push_back({m, master_plane});
        if (distance < face_distance[e])
          face_distance[e] = std::min(face_distance[e],
                                      lowest_height_over(master_faces.quads[m],
                                                         plane,
                                                         projection->box) -
                                        projection->max_height);
      }
  }

  std::vector<double>
  MortarCoupling::face_clearances(
    const std::vector<Tensor<1, 3>> &slave_displacement,
    const double                     master_displacement) const
  {
    std::vector<double> result(face_distance);
    for (unsigned int e = 0; e < result.size(); ++e)
      if (std::isfinite(result[e]))
        result[e] -= closure(e, slave_displacement, master_displacement);
    return result;
  }

  double
  MortarCoupling::closure(const unsigned int               e,
                          const std::vector<Tensor<1, 3>> &slave_displacement,
                          const double master_displacement) const
  {
    const auto &projection = slave_cache->projections[e];
    if (!projection || slave_displacement.empty())
      return master_displacement;
    double slave_closure = -std::numeric_limits<double>::infinity();
    for (const unsigned int j : slave.faces()[e].nodes)
      slave_closure =
        std::max(slave_closure,
                 slave_displacement[j] * projection->plane.normal());
    return slave_closure + master_displacement;
  }

  // Near faces, the faces around their nodes (integrated), and the nodes
  // with a face that is not integrated but could couple (left out).
  void
  MortarCoupling::choose_window_faces(const CouplingWindow &window,
                                      std::vector<bool>    &integrated,
                                      std::vector<bool>    &left_out)
  {
    const auto        &faces   = slave.faces();
    const unsigned int n_faces = faces.size();
    AssertThrow(window.face_clearance.size() == n_faces, ExcInternalError());
    window_width = window.width;
    std::vector<bool> in_window(nodes.size(), false);
    for (unsigned int e = 0; e < n_faces; ++e)
      {
        near_face[e] = window.face_clearance[e] < window.width;
        if (std::isfinite(face_distance[e]))
          ++stats.n_faces_in_reach;
        if (near_face[e])
          {
            ++stats.n_near_faces;
            for (const unsigned int j : faces[e].nodes)
              in_window[j] = true;
          }
      }
    left_out.assign(nodes.size(), false);
    for (unsigned int e = 0; e < n_faces; ++e)
      {
        integrated[e] = false;
        for (const unsigned int j : faces[e].nodes)
          integrated[e] = integrated[e] || in_window[j];
        if (integrated[e])
          ++stats.n_window_faces;
        else if (std::isfinite(face_distance[e]))
          for (const unsigned int j : faces[e].nodes)
            left_out[j] = true;
      }
    for (const bool out : left_out)
      stats.n_left_out_nodes += out;
  }

  bool
  MortarCoupling::window_holds(
    const std::vector<Tensor<1, 3>> &slave_displacement,
    const double                     master_displacement) const
  {
    if (window_width == 0)
      return true;
    for (unsigned int e = 0; e < near_face.size(); ++e)
      if (!near_face[e] && std::isfinite(face_distance[e]) &&
          !(face_distance[e] -
              closure(e, slave_displacement, master_displacement) >=
            0.5 * window_width))
        return false;
    return true;
  }

} // namespace TKR::Mortar
