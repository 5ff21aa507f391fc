// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// MortarCoupling: the slave side, the integration cells of the coupled
// face pairs (coupling_pairs.cc finds them), the fitted weights, D and M,
// and the nodes' rows, gaps and coverage.

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/lac/full_matrix.h>

#include <tkr/mortar/mortar_coupling.h>
#include <tkr/mortar/surface_geometry.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "coupling_data.h"

namespace TKR::Mortar
{
  using namespace dealii;

  namespace
  {
    /**
     * The exact integrals of phi_1, phi_2, phi_3 over the unit square with
     * the weight |J|, J = j_0 + j_1 xi_0 + j_2 xi_1 the Jacobian determinant
     * of a convex plane bilinear map (so of one sign): the integrals of the
     * shape functions over the projected face, in the plane's measure. The
     * integrand has degree at most 3 in each variable, so 2 x 2 Gauss
     * points are exact.
     */
    std::array<double, 3>
    plane_moments(const std::array<double, 3> &j)
    {
      static const QGauss<2> gauss(2);
      std::array<double, 3>  result{};
      for (unsigned int q = 0; q < gauss.size(); ++q)
        {
          const Point<2> &x = gauss.point(q);
          const double    J = std::abs(j[0] + j[1] * x[0] + j[2] * x[1]);
          const auto      N = BilinearQuad::shape_values(x);
          for (unsigned int i = 0; i < 3; ++i)
            result[i] += gauss.weight(q) * J * N[i + 1];
        }
      return result;
    }

    /**
     * The test functions on a fully covered face: the dual basis
     * psi_i = sum_k A_ik phi_k with A = D_e M_e^{-1}, where M_e and its row
     * sums D_e come from the face's own quadrature points, so that
     * sum_q W_q psi_i phi_k = delta_ik D_e,i holds to round-off. (@p mass
     * and @p mass_inverse: work space.)
     */
    void
    dual_basis_coefficients(const std::vector<std::array<double, 4>> &phi,
                            const std::vector<double>                &weight,
                            FullMatrix<double>                       &mass,
                            FullMatrix<double> &mass_inverse,
                            FullMatrix<double> &A)
    {
      mass.reinit(4, 4);
      mass_inverse.reinit(4, 4);
      for (unsigned int q = 0; q < phi.size(); ++q)
        for (unsigned int i = 0; i < 4; ++i)
          for (unsigned int k = 0; k < 4; ++k)
            mass(i, k) += weight[q] * phi[q][i] * phi[q][k];
      mass_inverse.invert(mass);
      for (unsigned int i = 0; i < 4; ++i)
        {
          double row_sum = 0;
          for (unsigned int k = 0; k < 4; ++k)
            row_sum += mass(i, k);
          for (unsigned int k = 0; k < 4; ++k)
            A(i, k) = row_sum * mass_inverse(i, k);
        }
    }
  } // namespace

  double
  MortarCoupling::dual_weight(const double coverage)
  {
    if (coverage <= dual_coverage)
      return 0.;
    const double s = (coverage - dual_coverage) / (1. - dual_coverage);
    return s * s * (3. - 2. * s);
  }

  double
  MortarCoupling::edge_offset(const double fraction, const double length)
  {
    if (fraction >= full_constraint_fraction)
      return 0.;
    const double r = (full_constraint_fraction - fraction) / fraction;
    return length * r * r;
  }

  void
  MortarCoupling::update_slave_cache(const std::vector<Point<3>> &positions)
  {
    const auto &slave_nodes = slave.nodes();
    bool        unchanged   = slave_cache != nullptr;
    for (unsigned int j = 0; unchanged && j < slave_nodes.size(); ++j)
      unchanged = slave_cache->positions[j] == positions[slave_nodes[j].vertex];
    if (unchanged)
      return;

    slave_cache = std::make_shared<SlaveCache>();
    for (const auto &node : slave_nodes)
      slave_cache->positions.push_back(positions[node.vertex]);
    // D_jj = int phi_j and the nodal normals over the whole slave surface.
    const auto measures = slave.nodal_measures(positions);
    slave_cache->D      = measures.area;
    slave_cache->normal = measures.normal;
    slave_cache->area   = measures.total_area;
    // The projections below read the normals of the nodes.
    nodes.assign(slave_nodes.size(), SlaveNode());
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        nodes[j].D      = measures.area[j];
        nodes[j].normal = measures.normal[j];
      }
    const unsigned int n_faces = slave.faces().size();
    slave_cache->projections.resize(n_faces);
    slave_cache->exact.resize(n_faces);
    for (unsigned int e = 0; e < n_faces; ++e)
      if (project_slave_face(e, positions, slave_cache->projections[e]))
        slave_cache->exact[e] = plane_moments(
          slave_cache->projections[e]->quad.determinant_coefficients());
  }

  MortarCoupling::MortarCoupling(const ContactSurface &slave,
                                 const ContactSurface &master)
    : slave(slave)
    , master(master)
  {}

  // Three passes: the integration cells of every slave face with Gauss
  // points; the fitted weights (they need the cells of a master face, which
  // come from several slave faces); the contributions of every slave face
  // to D and M. Then the nodes are finished.
  void
  MortarCoupling::reinit(const std::vector<Point<3>> &positions,
                         const double                 search_distance,
                         const Tensor<2, 3>          &master_rotation,
                         const CouplingWindow        *window)
  {
    ++n_reinits;
    update_slave_cache(positions);
    nodes.assign(slave.nodes().size(), SlaveNode());
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        nodes[j].D      = slave_cache->D[j];
        nodes[j].normal = slave_cache->normal[j];
      }
    stats                = CouplingStatistics();
    stats.slave_area     = slave_cache->area;
    stats.n_slave_faces  = slave.faces().size();
    stats.n_master_faces = master.faces().size();

    const MasterGeometry master_faces(master, positions);
    const unsigned int   n_faces = slave.faces().size();
    if (!scratch)
      scratch = std::make_shared<Accumulator>();
    Accumulator &accumulator = *scratch;
    accumulator.reset(nodes.size(), n_faces);
    auto &pairs = accumulator.pairs;
    face_distance.assign(n_faces, std::numeric_limits<double>::infinity());
    for (unsigned int e = 0; e < n_faces; ++e)
      find_pairs(e,
                 positions,
                 master_faces,
                 search_distance,
                 accumulator,
                 pairs[e]);

    std::vector<bool> integrated(n_faces, true), left_out;
    near_face.assign(n_faces, true);
    window_width = 0;
    if (window != nullptr && window->width > 0 &&
        !window->face_clearance.empty())
      choose_window_faces(*window, integrated, left_out);
    for (unsigned int e = 0; e < n_faces; ++e)
      if (integrated[e])
        make_cells(e, pairs[e], accumulator);
      else
        accumulator.faces[e].first_cell = accumulator.faces[e].end_cell =
          accumulator.cells.size();
    fit_weights(accumulator);
    for (unsigned int e = 0; e < n_faces; ++e)
      assemble_face(e, positions, accumulator);
    finish_nodes(positions, master_rotation, left_out, accumulator);
  }

  // The plane: normal to the averaged nodal normal, or to the face's own
  // normal where that is more than 60 degrees away or where the face's
  // projection would not be convex. False if even then it is not.
  bool
  MortarCoupling::project_slave_face(const unsigned int              e,
                                     const std::vector<Point<3>>    &positions,
                                     std::optional<SlaveProjection> &result)
  {
    const BilinearQuad slave_quad{slave.face_vertices(e, positions)};
    const Point2       centre(0.5, 0.5);
    Tensor<1, 3>       face_normal =
      slave.orientation(e, positions) * slave_quad.area_normal(centre);
    face_normal /= face_normal.norm();
    Tensor<1, 3> averaged;
    for (const unsigned int j : slave.faces()[e].nodes)
      averaged += nodes[j].normal;
    averaged /= averaged.norm();

    for (const Tensor<1, 3> &n0 : {averaged, face_normal})
      {
        if (!(n0 * face_normal > 0.5))
          continue;
        const AuxiliaryPlane plane(slave_quad.point(centre), n0);
        PlaneQuad            quad;
        for (unsigned int v = 0; v < 4; ++v)
          quad.vertices[v] = plane.coordinates(slave_quad.vertices[v]);
        const int orientation = quad.convex_orientation();
        if (orientation == 0)
          continue;
        Polygon outline = quad.outline();
        if (orientation < 0)
          std::reverse(outline.begin(), outline.end());
        double min_height = 1e300, max_height = -1e300;
        for (const auto &x : slave_quad.vertices)
          {
            min_height = std::min(min_height, plane.height(x));
            max_height = std::max(max_height, plane.height(x));
          }
        const BoundingBox<2> box  = BoundingBox<2>(outline);
        const double         area = signed_area(outline);
        result.emplace(SlaveProjection{plane,
                                       quad,
                                       outline,
                                       area,
                                       min_height,
                                       max_height,
                                       box});
        return true;
      }
    return false;
  }

  // The integration cells of slave face e (see the class documentation):
  // a cell for each pair that overlaps in the plane.
  void
  MortarCoupling::make_cells(const unsigned int           e,
                             const std::vector<FacePair> &pairs,
                             Accumulator                 &accumulator)
  {
    auto &face      = accumulator.faces[e];
    face.first_cell = face.end_cell = accumulator.cells.size();
    const std::optional<SlaveProjection> &projection =
      slave_cache->projections[e];
    if (!projection)
      return;
    face.n0         = projection->plane.normal();
    face.plane_area = projection->area;
    face.exact      = slave_cache->exact[e];
    const PlaneQuadInverse slave_inverse(projection->quad);
    for (const FacePair &pair : pairs)
      make_cell(e, pair, *projection, slave_inverse, accumulator);

    face.end_cell = accumulator.cells.size();
    if (face.end_cell == face.first_cell)
      return;
    ++stats.n_integrated_faces;
    const double coverage = face.covered_plane_area / face.plane_area;
    face.coverage         = coverage;
    face.overcovered      = coverage > 1. + 1e-9;
    face.fully_covered    = !face.overcovered && coverage >= 1. - 1e-9;
    if (face.overcovered)
      ++stats.n_overcovered_faces;
    else if (face.fully_covered)
      ++stats.n_fully_covered_faces;
    else
      ++stats.n_partly_covered_faces;
  }

  // The cell of slave face e and the master face of a pair of
  // find_pairs(), if their projections overlap.
  void
  MortarCoupling::make_cell(const unsigned int      e,
                            const FacePair         &pair,
                            const SlaveProjection  &slave_face,
                            const PlaneQuadInverse &slave_inverse,
                            Accumulator            &accumulator)
  {
    const MasterProjection &projection   = pair.projection;
    const PlaneQuad        &master_plane = projection.quad;
    const int               orientation  = master_plane.convex_orientation();
    if (orientation == 0)
      {
        ++stats.n_rejected_pairs;
        return;
      }
    Polygon master_outline = master_plane.outline();
    if (orientation < 0)
      std::reverse(master_outline.begin(), master_outline.end());
    const Polygon cell = clip_polygon(master_outline, slave_face.outline);
    const double  area = cell.empty() ? 0. : signed_area(cell);
    if (area <= 1e-12 * slave_face.area)
      return;

    const unsigned int begin = accumulator.points.size();
    if (!cell_quadrature.append_points(cell,
                                       slave_inverse,
                                       PlaneQuadInverse(master_plane),
                                       accumulator.points))
      {
        ++stats.n_rejected_pairs;
        return;
      }
    accumulator.cells.push_back(
      {e,
       pair.master_face,
       begin,
       static_cast<unsigned int>(accumulator.points.size()),
       area,
       std::abs(signed_area(master_outline)),
       plane_moments(master_plane.determinant_coefficients()),
       projection.max_beta - projection.min_beta <=
         1e-12 * std::sqrt(slave_face.area)});
    accumulator.faces[e].covered_plane_area += area;
  }

  // The fitted weights (CellQuadrature). The Gauss points of the cells
  // integrate the shape functions only approximately. Over a fully covered
  // slave face, though, the integrals of its shape functions must be their
  // exact integrals over the face's projection; over a fully covered master
  // face that is flat and whose cells all lie in one plane parallel to it
  // (a flat interface) those of the master face's. (Only there does the
  // transfer of a uniform pressure need the master integrals, and only
  // there is the plane's measure the master face's own.) fit_weights() changes
  // the weights by the least amount that makes them so. Then sum_j D_jj over a
  // fully covered face is exact and, on a flat interface, so is the transfer of
  // a uniform pressure to the master nodes (the contact patch test).
  void
  MortarCoupling::fit_weights(Accumulator &accumulator)
  {
    const auto              &cells = accumulator.cells;
    std::vector<FittingFace> faces;
    for (const auto &face : accumulator.faces)
      if (face.fully_covered)
        {
          faces.push_back({{}, false, face.exact});
          for (unsigned int c = face.first_cell; c < face.end_cell; ++c)
            faces.back().cells.push_back(c);
        }

    std::vector<std::vector<unsigned int>> master_cells(master.faces().size());
    for (unsigned int c = 0; c < cells.size(); ++c)
      if (!accumulator.faces[cells[c].slave_face].overcovered)
        master_cells[cells[c].master_face].push_back(c);
    for (const auto &list : master_cells)
      {
        double fraction = 0;
        bool   parallel = true;
        for (const unsigned int c : list)
          {
            fraction += cells[c].area / cells[c].master_area;
            parallel = parallel && cells[c].master_parallel;
          }
        if (!list.empty() && parallel && std::abs(fraction - 1.) <= 1e-9)
          faces.push_back({list, true, cells[list[0]].master_exact});
      }

    std::vector<std::pair<unsigned int, unsigned int>> ranges(cells.size());
    std::vector<double>                                areas(cells.size());
    for (unsigned int c = 0; c < cells.size(); ++c)
      {
        ranges[c] = {cells[c].begin, cells[c].end};
        areas[c]  = cells[c].area;
      }
    if (!faces.empty())
      stats.fitting_error =
        Mortar::fit_weights(accumulator.points, ranges, areas, faces);
    stats.n_fitted_faces      = faces.size();
    stats.n_overlapping_pairs = cells.size();
    stats.n_quadrature_points = accumulator.points.size();
  }

  // The contributions of slave face e to D^c and M, with the dual basis
  // (fully covered face), the standard basis (a face less than
  // dual_coverage covered) or a blend of both.
  void
  MortarCoupling::assemble_face(const unsigned int           e,
                                const std::vector<Point<3>> &positions,
                                Accumulator                 &accumulator)
  {
    const auto &face = accumulator.faces[e];
    if (face.end_cell == face.first_cell || face.overcovered)
      return;
    const auto        &face_nodes = slave.faces()[e].nodes;
    const BilinearQuad slave_quad{slave.face_vertices(e, positions)};
    const auto        &cells  = accumulator.cells;
    const auto        &points = accumulator.points;
    const unsigned int begin  = cells[face.first_cell].begin;
    const unsigned int end    = cells[face.end_cell - 1].end;

    // Weights on the slave surface: dA_slave = dA_plane |a| / |n0 . a|
    // with a = dx/dxi_0 x dx/dxi_1.
    auto &phi    = accumulator.phi;
    auto &weight = accumulator.weight;
    phi.resize(end - begin);
    weight.resize(end - begin);
    for (unsigned int q = begin; q < end; ++q)
      {
        const Tensor<1, 3> a = slave_quad.area_normal(points[q].slave_xi);
        weight[q - begin] = points[q].weight * a.norm() / std::abs(face.n0 * a);
        phi[q - begin]    = BilinearQuad::shape_values(points[q].slave_xi);
      }
    // psi = t psi^dual + (1 - t) phi with t = dual_weight(coverage): the
    // dual basis on a fully covered face, the standard one below
    // dual_coverage, blended continuously in between.
    FullMatrix<double> &A = accumulator.dual;
    A.reinit(4, 4);
    const double t =
      face.fully_covered ? 1. : dual_weight(std::min(face.coverage, 1.));
    if (t > 0)
      {
        dual_basis_coefficients(phi,
                                weight,
                                accumulator.mass,
                                accumulator.mass_inverse,
                                A);
        A *= t;
      }
    for (unsigned int i = 0; i < 4; ++i)
      A(i, i) += 1. - t;

    // D^c_i = sum_q W_q phi_i(xi_q); per cell (one master face) the block
    // sum_q W_q psi_i(xi_q) phi^m_l(eta_q) of M for the face's four slave
    // nodes i and the master face's four nodes l.
    for (unsigned int i = 0; i < 4; ++i)
      for (unsigned int q = 0; q < end - begin; ++q)
        accumulator.covered_D[face_nodes[i]] += weight[q] * phi[q][i];
    // The gap gradient's n_m / (n_m . n_0) does not depend on the length
    // or the sign of the master's area normal.
    std::array<double, 4> n_dot_n0;
    for (unsigned int i = 0; i < 4; ++i)
      n_dot_n0[i] = nodes[face_nodes[i]].normal * face.n0;
    for (unsigned int c = face.first_cell; c < face.end_cell; ++c)
      {
        double             block[4][4] = {};
        const BilinearQuad master_quad{
          master.face_vertices(cells[c].master_face, positions)};
        for (unsigned int q = cells[c].begin; q < cells[c].end; ++q)
          {
            const auto N_m = BilinearQuad::shape_values(points[q].master_xi);
            const Tensor<1, 3> a = master_quad.area_normal(points[q].master_xi);
            const double       a_n0 = a * face.n0;
            const Tensor<1, 3> direction =
              std::abs(a_n0) > 1e-3 * a.norm() ? a / a_n0 : face.n0;
            for (unsigned int i = 0; i < 4; ++i)
              {
                double psi = 0;
                for (unsigned int k = 0; k < 4; ++k)
                  psi += A(i, k) * phi[q - begin][k];
                for (unsigned int l = 0; l < 4; ++l)
                  block[i][l] += weight[q - begin] * psi * N_m[l];
                accumulator.gap_gradient[face_nodes[i]] +=
                  weight[q - begin] * psi * n_dot_n0[i] * direction;
              }
          }
        const auto &master_nodes = master.faces()[cells[c].master_face].nodes;
        for (unsigned int i = 0; i < 4; ++i)
          for (unsigned int l = 0; l < 4; ++l)
            accumulator.rows[face_nodes[i]].emplace_back(master_nodes[l],
                                                         block[i][l]);
      }
  }

  // Per node: merge the row of M, scale it (and so the weighted gap) from
  // the covered area D^c_j to the nodal area D_jj, decide whether the node
  // is covered, and compute the weighted gap with the edge offset of the
  // class documentation, and the master point.
  void
  MortarCoupling::finish_nodes(const std::vector<Point<3>> &positions,
                               const Tensor<2, 3>          &master_rotation,
                               const std::vector<bool>     &left_out,
                               Accumulator                 &accumulator)
  {
    const auto &master_nodes = master.nodes();
    const auto &slave_list   = slave.nodes();
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        SlaveNode &node = nodes[j];
        auto      &row  = accumulator.rows[j];
        if (!left_out.empty() && left_out[j])
          {
            node.master_normal = transpose(master_rotation) * node.normal;
            continue;
          }
        const double covered_D = accumulator.covered_D[j];
        stats.covered_area += covered_D;
        node.covered_fraction = covered_D / node.D;
        node.master_normal    = transpose(master_rotation) * node.normal;

        std::sort(row.begin(), row.end(), [](const auto &a, const auto &b) {
          return a.first < b.first;
        });
        node.M.clear();
        for (const auto &[k, value] : row)
          if (!node.M.empty() && node.M.back().first == k)
            node.M.back().second += value;
          else
            node.M.emplace_back(k, value);
        if (!(covered_D > 0))
          {
            node.M.clear();
            continue;
          }
        const double scale = node.D / covered_D;
        for (auto &entry : node.M)
          entry.second *= scale;
        node.gap_gradient = scale * accumulator.gap_gradient[j];

        const bool fully = node.covered_fraction >= 1. - 1e-9;
        node.covered     = node.covered_fraction >= min_covered_fraction;
        if (node.covered)
          {
            ++stats.n_covered_nodes;
            if (!fully)
              ++stats.n_partly_covered_nodes;
          }
        else
          ++stats.n_uncovered_touched_nodes;

        Tensor<1, 3> mortar_difference =
          -node.D * positions[slave_list[j].vertex];
        double row_sum = 0;
        for (const auto &[k, value] : node.M)
          {
            mortar_difference += value * positions[master_nodes[k].vertex];
            node.master_point += value * positions[master_nodes[k].vertex];
            row_sum += value;
          }
        node.gap_offset = edge_offset(node.covered_fraction, std::sqrt(node.D));
        node.weighted_gap =
          node.normal * mortar_difference + node.D * node.gap_offset;
        if (row_sum != 0.)
          node.master_point /= row_sum;
      }
  }
} // namespace TKR::Mortar
