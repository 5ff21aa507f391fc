// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/lac/full_matrix.h>

#include <deal.II/numerics/rtree.h>

#include <tkr/mortar/mortar_coupling.h>
#include <tkr/mortar/surface_geometry.h>

#include <map>

namespace TKR::Mortar
{
  using namespace dealii;

  namespace
  {
    /** Bounding box of a face. */
    BoundingBox<3>
    face_box(const std::array<Point<3>, 4> &x)
    {
      return BoundingBox<3>(std::vector<Point<3>>(x.begin(), x.end()));
    }

    /**
     * Coefficients A of the dual basis psi_i = sum_k A_ik phi_k on one
     * slave face: A = D_e M_e^{-1} with the face mass matrix M_e and its row
     * sums D_e, which makes int psi_i phi_k = delta_ik int phi_i.
     */
    FullMatrix<double>
    dual_basis_coefficients(const BilinearQuad &quad)
    {
      FullMatrix<double> mass(4, 4), A(4, 4), mass_inverse(4, 4);
      const QGauss<2>    quadrature(3);
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        {
          const auto   N = BilinearQuad::shape_values(quadrature.point(q));
          const double JxW =
            quad.area_normal(quadrature.point(q)).norm() * quadrature.weight(q);
          for (unsigned int i = 0; i < 4; ++i)
            for (unsigned int k = 0; k < 4; ++k)
              mass(i, k) += N[i] * N[k] * JxW;
        }
      mass_inverse.invert(mass);
      for (unsigned int i = 0; i < 4; ++i)
        {
          double row_sum = 0;
          for (unsigned int k = 0; k < 4; ++k)
            row_sum += mass(i, k);
          for (unsigned int k = 0; k < 4; ++k)
            A(i, k) = row_sum * mass_inverse(i, k);
        }
      return A;
    }
  } // namespace

  MortarCoupling::MortarCoupling(const ContactSurface &slave,
                                 const ContactSurface &master)
    : slave(slave)
    , master(master)
  {}

  void
  MortarCoupling::reinit(const std::vector<Point<3>> &positions,
                         const double                 search_distance,
                         const Tensor<2, 3>          &master_rotation)
  {
    const auto &slave_faces  = slave.faces();
    const auto &master_faces = master.faces();
    nodes.assign(slave.nodes().size(), SlaveNode());
    stats                = CouplingStatistics();
    stats.n_slave_faces  = slave_faces.size();
    stats.n_master_faces = master_faces.size();

    // Master faces: geometry, outward normal at the centre, R-tree.
    const Point2              centre(0.5, 0.5);
    std::vector<BilinearQuad> master_quads(master_faces.size());
    std::vector<Tensor<1, 3>> master_normals(master_faces.size());
    std::vector<std::pair<BoundingBox<3>, unsigned int>> boxes;
    for (unsigned int m = 0; m < master_faces.size(); ++m)
      {
        master_quads[m].vertices = master.face_vertices(m, positions);
        const Tensor<1, 3> n     = master_quads[m].area_normal(centre);
        master_normals[m] = master.orientation(m, positions) * n / n.norm();
        boxes.emplace_back(face_box(master_quads[m].vertices), m);
      }
    const auto tree = pack_rtree(boxes);

    // D_jj and the nodal normals: integrals of phi_j and phi_j n over the
    // whole slave surface.
    const QGauss<2> face_quadrature(2);
    for (unsigned int e = 0; e < slave_faces.size(); ++e)
      {
        const BilinearQuad quad{slave.face_vertices(e, positions)};
        const double       sign = slave.orientation(e, positions);
        for (unsigned int q = 0; q < face_quadrature.size(); ++q)
          {
            const auto N = BilinearQuad::shape_values(face_quadrature.point(q));
            const Tensor<1, 3> dA = sign *
                                    quad.area_normal(face_quadrature.point(q)) *
                                    face_quadrature.weight(q);
            for (unsigned int i = 0; i < 4; ++i)
              {
                SlaveNode &node = nodes[slave_faces[e].nodes[i]];
                node.D += N[i] * dA.norm();
                node.normal += N[i] * dA;
              }
          }
      }
    for (auto &node : nodes)
      {
        node.normal /= node.normal.norm();
        stats.slave_area += node.D;
      }

    // M_jk by segment-based integration over the overlap of each slave face
    // with the projections of the master faces near it.
    const QGaussSimplex<2>                      triangle_quadrature(3);
    std::vector<std::map<unsigned int, double>> M(nodes.size());
    std::vector<bool> face_covered(slave_faces.size());
    std::vector<std::pair<BoundingBox<3>, unsigned int>> candidates;
    for (unsigned int e = 0; e < slave_faces.size(); ++e)
      {
        const BilinearQuad       slave_quad{slave.face_vertices(e, positions)};
        const FullMatrix<double> A = dual_basis_coefficients(slave_quad);
        Tensor<1, 3>             n0 =
          slave.orientation(e, positions) * slave_quad.area_normal(centre);
        n0 /= n0.norm();

        // Candidates: master faces whose boxes meet the slave face's box
        // stretched along its normal by the search distance (and by a
        // little tangentially). Stretching only along the normal keeps the
        // number of candidates per face independent of the mesh size.
        candidates.clear();
        {
          BoundingBox<3> box        = face_box(slave_quad.vertices);
          auto           corners    = box.get_boundary_points();
          const double   tangential = 0.05 * box.side_length(0) +
                                    0.05 * box.side_length(1) +
                                    0.05 * box.side_length(2);
          for (unsigned int d = 0; d < 3; ++d)
            {
              const double margin =
                search_distance * std::abs(n0[d]) + tangential;
              corners.first[d] -= margin;
              corners.second[d] += margin;
            }
          tree.query(boost::geometry::index::intersects(
                       BoundingBox<3>(corners)),
                     std::back_inserter(candidates));
        }
        stats.n_candidate_pairs += candidates.size();

        double covered = 0;
        for (const auto &candidate : candidates)
          {
            const unsigned int  m           = candidate.second;
            const BilinearQuad &master_quad = master_quads[m];
            if (master_normals[m] * n0 >= 0)
              continue; // not facing the slave face
            // Project the master vertices along n0 into the slave face's
            // parameter square; polygon order 0, 1, 3, 2.
            Polygon polygon;
            double  min_beta = 1e300, max_beta = -1e300;
            bool    ok = true;
            for (const unsigned int v : {0u, 1u, 3u, 2u})
              {
                Point2 xi;
                double beta;
                ok = ok &&
                     slave_quad.project(master_quad.vertices[v], n0, xi, beta);
                polygon.push_back(xi);
                min_beta = std::min(min_beta, beta);
                max_beta = std::max(max_beta, beta);
              }
            if (!ok || min_beta > search_distance ||
                max_beta < -search_distance)
              continue;
            const Polygon overlap = clip_to_unit_square(polygon);
            if (overlap.empty())
              continue;
            ++stats.n_overlapping_pairs;
            covered += signed_area(overlap);

            // Fan triangulation of the (convex) overlap polygon.
            for (unsigned int t = 1; t + 1 < overlap.size(); ++t)
              {
                const Point2 &a = overlap[0], &b = overlap[t],
                             &c = overlap[t + 1];
                const double triangle_area =
                  0.5 *
                  std::abs((b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0]);
                if (triangle_area < 1e-16)
                  continue;
                for (unsigned int q = 0; q < triangle_quadrature.size(); ++q)
                  {
                    const Point<2> &s   = triangle_quadrature.point(q);
                    const Point2    xi  = a + s[0] * (b - a) + s[1] * (c - a);
                    const double    JxW = 2. * triangle_area *
                                       triangle_quadrature.weight(q) *
                                       slave_quad.area_normal(xi).norm();
                    Point2 eta;
                    double beta;
                    if (!master_quad.project(slave_quad.point(xi),
                                             n0,
                                             eta,
                                             beta))
                      continue;
                    // The overlap has straight edges in the slave parameter
                    // plane; the master face's image has slightly curved
                    // ones. Stay on the master face.
                    for (unsigned int d = 0; d < 2; ++d)
                      eta[d] = std::min(1., std::max(0., eta[d]));
                    const auto N_s = BilinearQuad::shape_values(xi);
                    const auto N_m = BilinearQuad::shape_values(eta);
                    for (unsigned int i = 0; i < 4; ++i)
                      {
                        double psi = 0;
                        for (unsigned int k = 0; k < 4; ++k)
                          psi += A(i, k) * N_s[k];
                        auto &row = M[slave_faces[e].nodes[i]];
                        for (unsigned int l = 0; l < 4; ++l)
                          row[master_faces[m].nodes[l]] += psi * N_m[l] * JxW;
                      }
                  }
              }
          }
        // The overlaps tile the slave face exactly if the master surface
        // covers it once; more than the face means folded coverage.
        face_covered[e] = std::abs(covered - 1.) < 1e-8;
      }

    // Covered nodes, their M rows and weighted gaps.
    for (unsigned int e = 0; e < slave_faces.size(); ++e)
      if (face_covered[e])
        {
          const BilinearQuad quad{slave.face_vertices(e, positions)};
          for (unsigned int q = 0; q < face_quadrature.size(); ++q)
            stats.covered_area +=
              quad.area_normal(face_quadrature.point(q)).norm() *
              face_quadrature.weight(q);
        }
    const auto &master_nodes = master.nodes();
    const auto &slave_list   = slave.nodes();
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        SlaveNode &node = nodes[j];
        node.covered    = true;
        for (const unsigned int e : slave.node_faces()[j])
          node.covered = node.covered && face_covered[e];
        node.M.assign(M[j].begin(), M[j].end());
        Tensor<1, 3> mortar_difference =
          -node.D * positions[slave_list[j].vertex];
        for (const auto &[k, value] : node.M)
          mortar_difference += value * positions[master_nodes[k].vertex];
        node.weighted_gap  = node.normal * mortar_difference;
        node.master_normal = transpose(master_rotation) * node.normal;
        double row_sum     = 0;
        for (const auto &[k, value] : node.M)
          {
            row_sum += value;
            node.master_point += value * positions[master_nodes[k].vertex];
          }
        if (row_sum != 0.)
          node.master_point /= row_sum;
        if (node.covered)
          ++stats.n_covered_nodes;
      }
  }
} // namespace TKR::Mortar
