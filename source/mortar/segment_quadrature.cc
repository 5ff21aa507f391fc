// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/mortar/segment_quadrature.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <cmath>

namespace TKR::Mortar
{
  using namespace dealii;

  namespace
  {
    /** The intersection of two quadrilaterals has at most eight vertices. */
    constexpr unsigned int max_vertices = 8;

    /** 1, phi_1, phi_2, phi_3 at @p x. */
    std::array<double, 4>
    moment_functions(const Point2 &x)
    {
      return {{1., x[0] * (1 - x[1]), (1 - x[0]) * x[1], x[0] * x[1]}};
    }
  } // namespace

  CellQuadrature::CellQuadrature()
    : triangle_rule(3)
  {}

  // The cell's vertices are mapped back to both faces first; their
  // parameters (barycentric interpolation) give the starting values of
  // Newton's method at the Gauss points, so that two or three steps suffice.
  // The fan of triangles starts at vertex 0, or at the vertex average of a
  // triangular cell (so that there are more points than fitted moments).
  bool
  CellQuadrature::append_points(const Polygon          &cell,
                                const PlaneQuadInverse &slave,
                                const PlaneQuadInverse &master,
                                std::vector<CellPoint> &points) const
  {
    const unsigned int n_vertices = cell.size();
    Assert(n_vertices >= 3 && n_vertices <= max_vertices, ExcInternalError());
    const double       area  = signed_area(cell);
    const unsigned int first = points.size();

    std::array<Point2, max_vertices + 1> p, xi, eta;
    for (unsigned int v = 0; v < n_vertices; ++v)
      {
        p[v] = cell[v];
        if (!slave(p[v], xi[v], false) || !master(p[v], eta[v], false))
          return false;
      }

    const auto add_triangle =
      [&](const unsigned int a, const unsigned int b, const unsigned int c) {
        const Tensor<1, 2> e0 = p[b] - p[a], e1 = p[c] - p[a];
        const double triangle_area = 0.5 * (e0[0] * e1[1] - e0[1] * e1[0]);
        if (triangle_area <= 1e-14 * area)
          return true;
        for (unsigned int q = 0; q < triangle_rule.size(); ++q)
          {
            const double s = triangle_rule.point(q)[0];
            const double t = triangle_rule.point(q)[1];
            CellPoint    point;
            point.slave_xi = xi[a] + s * (xi[b] - xi[a]) + t * (xi[c] - xi[a]);
            point.master_xi =
              eta[a] + s * (eta[b] - eta[a]) + t * (eta[c] - eta[a]);
            point.weight = 2. * triangle_area * triangle_rule.weight(q);
            const Point2 x(p[a] + s * e0 + t * e1);
            if (!slave(x, point.slave_xi, true) ||
                !master(x, point.master_xi, true))
              return false;
            points.push_back(point);
          }
        return true;
      };

    bool ok = true;
    if (n_vertices == 3)
      {
        const unsigned int c = 3;
        p[c] = xi[c] = eta[c] = Point2();
        for (unsigned int v = 0; v < 3; ++v)
          {
            p[c] += p[v] / 3.;
            xi[c] += xi[v] / 3.;
            eta[c] += eta[v] / 3.;
          }
        for (unsigned int v = 0; v < 3 && ok; ++v)
          ok = add_triangle(c, v, (v + 1) % 3);
      }
    else
      for (unsigned int v = 1; v + 1 < n_vertices && ok; ++v)
        ok = add_triangle(0, v, v + 1);
    if (!ok || points.size() == first)
      {
        points.resize(first);
        return false;
      }
    return true;
  }

  namespace
  {
    /**
     * The conditions of fit_weights() that involve the points of one cell:
     * the cell's area (unknown index @p cell_unknown) and the shape functions
     * of up to two faces (first unknown of each, -1 if none).
     */
    struct CellConditions
    {
      int cell_unknown = -1, slave_unknown = -1, master_unknown = -1;
    };

    /** The numbering of the conditions (the unknowns lambda). */
    struct Conditions
    {
      std::vector<CellConditions> cells;
      /** First unknown of each face (three each). */
      std::vector<unsigned int> face_first;
      unsigned int              n_unknowns = 0;
      /** Whether some cell belongs to two faces. */
      bool coupled = false;
      /** The right-hand side b (cell areas, exact face integrals). */
      std::vector<double> targets;
    };

    /** Unknowns and values of the conditions at one point. */
    unsigned int
    condition_values(const CellConditions        &conditions,
                     const CellPoint             &point,
                     std::array<unsigned int, 7> &index,
                     std::array<double, 7>       &value)
    {
      unsigned int n = 0;
      index[n]       = conditions.cell_unknown;
      value[n++]     = 1.;
      for (const int face :
           {conditions.slave_unknown, conditions.master_unknown})
        if (face >= 0)
          {
            const auto f = moment_functions(face == conditions.slave_unknown ?
                                              point.slave_xi :
                                              point.master_xi);
            for (unsigned int r = 0; r < 3; ++r)
              {
                index[n]   = face + r;
                value[n++] = f[r + 1];
              }
          }
      return n;
    }

    // Unknowns: the cells of some face (in the order of the faces' lists, so
    // that the cells of a face have consecutive unknowns when no cell
    // belongs to two faces), then three per face.
    Conditions
    number_conditions(const std::vector<double>      &cell_areas,
                      const std::vector<FittingFace> &faces)
    {
      Conditions conditions;
      conditions.cells.resize(cell_areas.size());
      for (const auto &face : faces)
        for (const unsigned int c : face.cells)
          if (conditions.cells[c].cell_unknown < 0)
            conditions.cells[c].cell_unknown = conditions.n_unknowns++;
          else
            conditions.coupled = true;
      conditions.targets.resize(conditions.n_unknowns + 3 * faces.size());
      for (unsigned int c = 0; c < cell_areas.size(); ++c)
        if (conditions.cells[c].cell_unknown >= 0)
          conditions.targets[conditions.cells[c].cell_unknown] = cell_areas[c];
      for (const auto &face : faces)
        {
          const unsigned int first = conditions.n_unknowns;
          conditions.face_first.push_back(first);
          for (const unsigned int c : face.cells)
            (face.master ? conditions.cells[c].master_unknown :
                           conditions.cells[c].slave_unknown) = first;
          for (unsigned int r = 0; r < 3; ++r)
            conditions.targets[first + r] = face.integrals[r];
          conditions.n_unknowns += 3;
        }
      return conditions;
    }

    /** Calls f(q, n, index, value) for every point q of a cell with
     *  conditions. */
    template <typename Function>
    void
    for_each_point(
      const std::vector<CellPoint>                             &points,
      const std::vector<std::pair<unsigned int, unsigned int>> &cell_ranges,
      const Conditions                                         &conditions,
      const Function                                           &f)
    {
      std::array<unsigned int, 7> index;
      std::array<double, 7>       value;
      for (unsigned int c = 0; c < cell_ranges.size(); ++c)
        if (conditions.cells[c].cell_unknown >= 0)
          for (unsigned int q = cell_ranges[c].first; q < cell_ranges[c].second;
               ++q)
            {
              const unsigned int n =
                condition_values(conditions.cells[c], points[q], index, value);
              f(q, n, index, value);
            }
    }

    /** b - C w for the present weights. */
    std::vector<double>
    residual(const std::vector<CellPoint>                             &points,
             const std::vector<std::pair<unsigned int, unsigned int>> &ranges,
             const Conditions &conditions)
    {
      std::vector<double> r = conditions.targets;
      for_each_point(points,
                     ranges,
                     conditions,
                     [&](const unsigned int                 q,
                         const unsigned int                 n,
                         const std::array<unsigned int, 7> &index,
                         const std::array<double, 7>       &value) {
                       for (unsigned int k = 0; k < n; ++k)
                         r[index[k]] -= points[q].weight * value[k];
                     });
      return r;
    }

    /** Work space of refine() and of the dense solve_regularized(). */
    struct SolveScratch
    {
      FullMatrix<double> inverse;
      Vector<double>     residual, correction;
    };

    /**
     * Solve G x = b for the symmetric positive semidefinite G = C W C^T
     * (solve_regularized()). G is singular where conditions coincide (a
     * slave and a master face that are the same parallelogram, as in the
     * middle of the structured Hertz meshes), and b is then consistent:
     * iterated Tikhonov regularisation,
     * x_{k+1} = x_k + (G + eps diag G)^{-1} (b - G x_k) with eps = 1e-10,
     * three steps, each of which reduces the error of a component with
     * (scaled) eigenvalue sigma by the factor eps / (sigma + eps).
     */
    template <typename Matrix, typename Inverse>
    void
    refine(const Matrix         &G,
           const Inverse        &inverse,
           const Vector<double> &b,
           Vector<double>       &x,
           SolveScratch         &scratch)
    {
      x                          = 0.;
      Vector<double> &residual   = scratch.residual;
      Vector<double> &correction = scratch.correction;
      residual                   = b;
      correction.reinit(b.size(), true);
      for (unsigned int step = 0; step < 3; ++step)
        {
          inverse.vmult(correction, residual);
          x += correction;
          G.residual(residual, x, b);
        }
    }

    void
    solve_regularized(const FullMatrix<double> &G,
                      const Vector<double>     &b,
                      Vector<double>           &x,
                      SolveScratch             &scratch)
    {
      FullMatrix<double> &inverse = scratch.inverse;
      inverse                     = G;
      for (unsigned int i = 0; i < G.m(); ++i)
        inverse(i, i) += 1e-10 * std::abs(G(i, i)) + 1e-300;
      inverse.gauss_jordan();
      refine(G, inverse, b, x, scratch);
    }

    void
    solve_regularized(const SparseMatrix<double> &G,
                      const Vector<double>       &b,
                      Vector<double>             &x)
    {
      SparseMatrix<double> regularized(G.get_sparsity_pattern());
      regularized.copy_from(G);
      for (unsigned int i = 0; i < G.m(); ++i)
        regularized.diag_element(i) += 1e-10 * std::abs(G.diag_element(i));
      SparseDirectUMFPACK inverse;
      inverse.initialize(regularized);
      SolveScratch scratch;
      refine(G, inverse, b, x, scratch);
    }

    /** lambda from one small dense system (C W C^T) per face, for faces
     *  whose cells are disjoint. */
    std::vector<double>
    solve_per_face(
      const std::vector<CellPoint>                             &points,
      const std::vector<std::pair<unsigned int, unsigned int>> &ranges,
      const std::vector<FittingFace>                           &faces,
      const Conditions                                         &conditions,
      const std::vector<double>                                &rhs)
    {
      std::vector<double>         lambda(conditions.n_unknowns, 0.);
      std::array<unsigned int, 7> index;
      std::array<double, 7>       value;
      // (reused from face to face: their memory is kept)
      FullMatrix<double> G;
      Vector<double>     b, x;
      SolveScratch       scratch;
      for (unsigned int f = 0; f < faces.size(); ++f)
        {
          // Local unknowns: the face's cells (consecutive), then its three.
          const auto        &cells   = faces[f].cells;
          const unsigned int n_local = cells.size() + 3;
          const unsigned int first_cell =
            conditions.cells[cells[0]].cell_unknown;
          const unsigned int first_face = conditions.face_first[f];
          const auto         local      = [&](const unsigned int i) {
            return (i >= first_cell && i < first_cell + cells.size()) ?
                                  i - first_cell :
                                  i - first_face + cells.size();
          };
          G.reinit(n_local, n_local);
          b.reinit(n_local);
          x.reinit(n_local);
          for (const unsigned int c : cells)
            for (unsigned int q = ranges[c].first; q < ranges[c].second; ++q)
              {
                const unsigned int n = condition_values(conditions.cells[c],
                                                        points[q],
                                                        index,
                                                        value);
                std::array<unsigned int, 7> row;
                for (unsigned int k = 0; k < n; ++k)
                  row[k] = local(index[k]);
                for (unsigned int k = 0; k < n; ++k)
                  for (unsigned int l = 0; l < n; ++l)
                    G(row[k], row[l]) += points[q].weight * value[k] * value[l];
              }
          for (unsigned int i = 0; i < cells.size(); ++i)
            b(i) = rhs[first_cell + i];
          for (unsigned int r = 0; r < 3; ++r)
            b(cells.size() + r) = rhs[first_face + r];
          solve_regularized(G, b, x, scratch);
          for (unsigned int i = 0; i < cells.size(); ++i)
            lambda[first_cell + i] = x(i);
          for (unsigned int r = 0; r < 3; ++r)
            lambda[first_face + r] = x(cells.size() + r);
        }
      return lambda;
    }

    /** lambda from one sparse system C W C^T (UMFPACK). */
    std::vector<double>
    solve_coupled(
      const std::vector<CellPoint>                             &points,
      const std::vector<std::pair<unsigned int, unsigned int>> &ranges,
      const Conditions                                         &conditions,
      const std::vector<double>                                &rhs)
    {
      const unsigned int     n = conditions.n_unknowns;
      DynamicSparsityPattern dsp(n, n);
      for_each_point(points,
                     ranges,
                     conditions,
                     [&](const unsigned int,
                         const unsigned int                 n_values,
                         const std::array<unsigned int, 7> &index,
                         const std::array<double, 7> &) {
                       for (unsigned int k = 0; k < n_values; ++k)
                         for (unsigned int l = 0; l < n_values; ++l)
                           dsp.add(index[k], index[l]);
                     });
      SparsityPattern pattern;
      pattern.copy_from(dsp);
      SparseMatrix<double> G(pattern);
      for_each_point(points,
                     ranges,
                     conditions,
                     [&](const unsigned int                 q,
                         const unsigned int                 n_values,
                         const std::array<unsigned int, 7> &index,
                         const std::array<double, 7>       &value) {
                       for (unsigned int k = 0; k < n_values; ++k)
                         for (unsigned int l = 0; l < n_values; ++l)
                           G.add(index[k],
                                 index[l],
                                 points[q].weight * value[k] * value[l]);
                     });
      Vector<double> b(rhs.begin(), rhs.end()), x(n);
      solve_regularized(G, b, x);
      return std::vector<double>(x.begin(), x.end());
    }
  } // namespace

  // The conditions: per cell, sum_q w_q = area (exact already, up to
  // round-off); per face, sum_q w_q phi_i(x_q) = integral_i (i = 1, 2, 3)
  // over the points of its cells. The matrix C W C^T is assembled point by
  // point from the (at most seven) conditions a point enters.
  double
  fit_weights(
    std::vector<CellPoint>                                   &points,
    const std::vector<std::pair<unsigned int, unsigned int>> &cell_ranges,
    const std::vector<double>                                &cell_areas,
    const std::vector<FittingFace>                           &faces)
  {
    const Conditions          conditions = number_conditions(cell_areas, faces);
    const std::vector<double> rhs = residual(points, cell_ranges, conditions);
    const std::vector<double> lambda =
      conditions.coupled ?
        solve_coupled(points, cell_ranges, conditions, rhs) :
        solve_per_face(points, cell_ranges, faces, conditions, rhs);

    // The new weights, if no weight changes by more than half.
    std::vector<double> factor(points.size(), 1.);
    bool                acceptable = true;
    for_each_point(points,
                   cell_ranges,
                   conditions,
                   [&](const unsigned int                 q,
                       const unsigned int                 n,
                       const std::array<unsigned int, 7> &index,
                       const std::array<double, 7>       &value) {
                     for (unsigned int k = 0; k < n; ++k)
                       factor[q] += lambda[index[k]] * value[k];
                     acceptable =
                       acceptable && factor[q] > 0.5 && factor[q] < 1.5;
                   });
    if (!acceptable)
      return 1.;
    for (unsigned int q = 0; q < points.size(); ++q)
      points[q].weight *= factor[q];

    // The remaining error of the face integrals, relative to the faces'
    // areas.
    const std::vector<double> remaining =
      residual(points, cell_ranges, conditions);
    double error = 0;
    for (unsigned int f = 0; f < faces.size(); ++f)
      {
        double area = 0;
        for (const unsigned int c : faces[f].cells)
          area += cell_areas[c];
        for (unsigned int r = 0; r < 3; ++r)
          error =
            std::max(error,
                     std::abs(remaining[conditions.face_first[f] + r]) / area);
      }
    return error;
  }
} // namespace TKR::Mortar
