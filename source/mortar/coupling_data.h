// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Private to source/mortar: the data that MortarCoupling's two source
// files share (mortar_coupling.cc integrates the coupled face pairs,
// coupling_pairs.cc finds them, bounds their distances and chooses the
// coupling window).

#ifndef tkr_source_mortar_coupling_data_h
#define tkr_source_mortar_coupling_data_h

#include <deal.II/base/bounding_box.h>

#include <deal.II/lac/full_matrix.h>

#include <deal.II/numerics/rtree.h>

#include <tkr/mortar/mortar_coupling.h>
#include <tkr/mortar/surface_geometry.h>

#include <algorithm>
#include <array>
#include <optional>
#include <utility>
#include <vector>

namespace TKR::Mortar
{
  using BoxEntry = std::pair<dealii::BoundingBox<3>, unsigned int>;

  /** Bounding box of a face. */
  inline dealii::BoundingBox<3>
  face_box(const std::array<dealii::Point<3>, 4> &x)
  {
    return dealii::BoundingBox<3>(x);
  }

  /**
   * A master face @p quad seen from an auxiliary plane: its projection,
   * and the range of its vertices' heights above the plane.
   */
  struct MasterProjection
  {
    PlaneQuad quad;
    double    min_beta = 1e300, max_beta = -1e300;

    MasterProjection(const AuxiliaryPlane &plane, const BilinearQuad &face)
    {
      for (unsigned int v = 0; v < 4; ++v)
        {
          const double beta = plane.height(face.vertices[v]);
          min_beta          = std::min(min_beta, beta);
          max_beta          = std::max(max_beta, beta);
          quad.vertices[v]  = plane.coordinates(face.vertices[v]);
        }
    }
  };

  /** A master face that may couple to a slave face (find_pairs()), and
   *  its projection onto the slave face's plane. */
  struct MortarCoupling::FacePair
  {
    unsigned int     master_face;
    MasterProjection projection;
  };

  /**
   * What reinit() collects: the integration cells of all slave faces with
   * their quadrature points (first pass), and then per slave node the
   * covered area int_covered phi_j, the (master node, value) contributions
   * to its row of M and to its gap gradient. Plus reused scratch space.
   */
  struct MortarCoupling::Accumulator
  {
    /** A slave face: its plane normal, its cells, and the exact integrals
     *  of its shape functions phi_1..3 over its projection. */
    struct Face
    {
      dealii::Tensor<1, 3>  n0;
      unsigned int          first_cell = 0, end_cell = 0;
      double                plane_area = 0, covered_plane_area = 0;
      std::array<double, 3> exact{};
      /** The part of the projection covered by master faces. */
      double coverage      = 0;
      bool   fully_covered = false, overcovered = false;
    };
    /** An integration cell: faces, points, area, and the master face's
     *  projection: its area, the exact integrals of its shape functions
     *  phi_1..3 over it, and whether the master face is flat and parallel
     *  to the plane (then the projection's measure is the face's). */
    struct Cell
    {
      unsigned int          slave_face, master_face, begin, end;
      double                area, master_area;
      std::array<double, 3> master_exact;
      bool                  master_parallel;
    };

    std::vector<Face>      faces;
    std::vector<Cell>      cells;
    std::vector<CellPoint> points;

    std::vector<double>                                       covered_D;
    std::vector<dealii::Tensor<1, 3>>                         gap_gradient;
    std::vector<std::vector<std::pair<unsigned int, double>>> rows;

    std::vector<BoxEntry>              candidates;
    std::vector<std::vector<FacePair>> pairs;
    std::vector<std::array<double, 4>> phi;
    std::vector<double>                weight;
    /** A face's dual basis coefficients, and work space for them. */
    dealii::FullMatrix<double> dual, mass, mass_inverse;

    /** Empty for a coupling of @p n_nodes slave nodes and @p n_faces slave
     *  faces; the vectors keep their memory from the last reinit(). */
    void
    reset(const unsigned int n_nodes, const unsigned int n_faces)
    {
      faces.assign(n_faces, Face());
      cells.clear();
      points.clear();
      covered_D.assign(n_nodes, 0.);
      gap_gradient.assign(n_nodes, dealii::Tensor<1, 3>());
      rows.resize(n_nodes);
      for (auto &row : rows)
        row.clear();
      pairs.resize(n_faces);
      for (auto &face_pairs : pairs)
        face_pairs.clear();
    }
  };

  /** The master surface at the current positions. */
  struct MortarCoupling::MasterGeometry
  {
    std::vector<BilinearQuad> quads;
    /** Outward unit normals at the face centres. */
    std::vector<dealii::Tensor<1, 3>> normals;
    dealii::RTree<BoxEntry>           tree;

    MasterGeometry(const ContactSurface                &master,
                   const std::vector<dealii::Point<3>> &positions)
    {
      const Point2          centre(0.5, 0.5);
      const unsigned int    n_faces = master.faces().size();
      std::vector<BoxEntry> boxes;
      quads.resize(n_faces);
      normals.resize(n_faces);
      for (unsigned int m = 0; m < n_faces; ++m)
        {
          quads[m].vertices            = master.face_vertices(m, positions);
          const dealii::Tensor<1, 3> n = quads[m].area_normal(centre);
          normals[m] = master.orientation(m, positions) * n / n.norm();
          boxes.emplace_back(face_box(quads[m].vertices), m);
        }
      tree = dealii::pack_rtree(boxes);
    }
  };

  /**
   * A slave face in its auxiliary plane: the plane, the face's projection
   * and its outline (counter-clockwise), its area and box in the plane, and
   * the range of its vertices' heights above the plane.
   */
  struct MortarCoupling::SlaveProjection
  {
    AuxiliaryPlane         plane;
    PlaneQuad              quad;
    Polygon                outline;
    double                 area, min_height, max_height;
    dealii::BoundingBox<2> box;
  };

  /** The slave-side data of the last slave geometry. */
  struct MortarCoupling::SlaveCache
  {
    /** The slave vertices' positions this data is for. */
    std::vector<dealii::Point<3>> positions;
    /** Nodal areas and normals, and the slave area. */
    std::vector<double>               D;
    std::vector<dealii::Tensor<1, 3>> normal;
    double                            area = 0;
    /** Each face's projection onto its plane (empty if not convex) and the
     *  exact integrals of its shape functions there. */
    std::vector<std::optional<SlaveProjection>> projections;
    std::vector<std::array<double, 3>>          exact;
  };

} // namespace TKR::Mortar

#endif
