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
                                const PlaneQuad        &slave,
                                const PlaneQuad        &master,
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
        if (!slave.inverse(p[v], xi[v]) || !master.inverse(p[v], eta[v]))
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
            if (!slave.inverse(x, point.slave_xi, nullptr, true) ||
                !master.inverse(x, point.master_xi, nullptr, true))
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
      unsigned int cell_unknown;
      int          slave_unknown = -1, master_unknown = -1;
    };

    /** Unknown indices and values of the conditions at one point. */
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
  } // namespace

  // The conditions: per cell, sum_q w_q = area (exact already, up to
  // round-off); per face, sum_q w_q phi_i(x_q) = integral_i (i = 1, 2, 3)
  // over the points of its cells. The matrix C W C^T is assembled point by
  // point from the (at most seven) conditions a point enters, dense per
  // face when the faces' cells are disjoint, else as one sparse matrix
  // (UMFPACK).
  double
  fit_weights(
    std::vector<CellPoint>                                   &points,
    const std::vector<std::pair<unsigned int, unsigned int>> &cell_ranges,
    const std::vector<double>                                &cell_areas,
    const std::vector<FittingFace>                           &faces)
  {
    // Unknowns: the cells of some face, then three per face.
    const unsigned int          n_cells = cell_ranges.size();
    std::vector<CellConditions> conditions(n_cells);
    std::vector<int>            cell_unknown(n_cells, -1);
    unsigned int                n_unknowns = 0;
    bool                        coupled    = false;
    for (const auto &face : faces)
      for (const unsigned int c : face.cells)
        if (cell_unknown[c] < 0)
          cell_unknown[c] = n_unknowns++;
        else
          coupled = true;
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_unknown[c] >= 0)
        conditions[c].cell_unknown = cell_unknown[c];
    std::vector<double> rhs(n_unknowns + 3 * faces.size(), 0.);
    for (unsigned int f = 0; f < faces.size(); ++f)
      {
        const int first = n_unknowns + 3 * f;
        for (const unsigned int c : faces[f].cells)
          (faces[f].master ? conditions[c].master_unknown :
                             conditions[c].slave_unknown) = first;
        for (unsigned int r = 0; r < 3; ++r)
          rhs[first + r] = faces[f].integrals[r];
      }
    n_unknowns += 3 * faces.size();
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_unknown[c] >= 0)
        rhs[cell_unknown[c]] = cell_areas[c];

    // rhs = b - C w.
    std::array<unsigned int, 7> index;
    std::array<double, 7>       value;
    const auto                  subtract_integrals = [&]() {
      for (unsigned int c = 0; c < n_cells; ++c)
        if (cell_unknown[c] >= 0)
          for (unsigned int q = cell_ranges[c].first; q < cell_ranges[c].second;
               ++q)
            {
              const unsigned int n =
                condition_values(conditions[c], points[q], index, value);
              for (unsigned int k = 0; k < n; ++k)
                rhs[index[k]] -= points[q].weight * value[k];
            }
    };
    subtract_integrals();

    std::vector<double> lambda(n_unknowns, 0.);
    if (!coupled)
      for (const auto &face : faces)
        {
          // Local unknowns: the face's cells, then its three conditions.
          const unsigned int        n_local = face.cells.size() + 3;
          std::vector<unsigned int> global(n_local);
          for (unsigned int i = 0; i < face.cells.size(); ++i)
            global[i] = cell_unknown[face.cells[i]];
          for (unsigned int r = 0; r < 3; ++r)
            global[face.cells.size() + r] =
              (face.master ? conditions[face.cells[0]].master_unknown :
                             conditions[face.cells[0]].slave_unknown) +
              r;
          // The face's cells have consecutive unknowns.
          const unsigned int first_cell = global[0];
          const unsigned int first_face = global[face.cells.size()];
          const auto         local      = [&](const unsigned int i) {
            return (i >= first_cell && i < first_cell + face.cells.size()) ?
                                  i - first_cell :
                                  i - first_face + face.cells.size();
          };
          FullMatrix<double> G(n_local, n_local);
          Vector<double>     b(n_local), x(n_local);
          for (const unsigned int c : face.cells)
            for (unsigned int q = cell_ranges[c].first;
                 q < cell_ranges[c].second;
                 ++q)
              {
                const unsigned int n =
                  condition_values(conditions[c], points[q], index, value);
                for (unsigned int k = 0; k < n; ++k)
                  for (unsigned int l = 0; l < n; ++l)
                    G(local(index[k]), local(index[l])) +=
                      points[q].weight * value[k] * value[l];
              }
          for (unsigned int i = 0; i < n_local; ++i)
            b(i) = rhs[global[i]];
          G.gauss_jordan();
          G.vmult(x, b);
          for (unsigned int i = 0; i < n_local; ++i)
            lambda[global[i]] = x(i);
        }
    else
      {
        DynamicSparsityPattern dsp(n_unknowns, n_unknowns);
        for (unsigned int c = 0; c < n_cells; ++c)
          if (cell_unknown[c] >= 0)
            {
              const unsigned int n =
                condition_values(conditions[c],
                                 points[cell_ranges[c].first],
                                 index,
                                 value);
              for (unsigned int k = 0; k < n; ++k)
                for (unsigned int l = 0; l < n; ++l)
                  dsp.add(index[k], index[l]);
            }
        SparsityPattern pattern;
        pattern.copy_from(dsp);
        SparseMatrix<double> G(pattern);
        for (unsigned int c = 0; c < n_cells; ++c)
          if (cell_unknown[c] >= 0)
            for (unsigned int q = cell_ranges[c].first;
                 q < cell_ranges[c].second;
                 ++q)
              {
                const unsigned int n =
                  condition_values(conditions[c], points[q], index, value);
                for (unsigned int k = 0; k < n; ++k)
                  for (unsigned int l = 0; l < n; ++l)
                    G.add(index[k],
                          index[l],
                          points[q].weight * value[k] * value[l]);
              }
        SparseDirectUMFPACK solver;
        solver.initialize(G);
        Vector<double> x(rhs.begin(), rhs.end());
        solver.solve(x);
        std::copy(x.begin(), x.end(), lambda.begin());
      }

    // The new weights, if no weight changes by more than half.
    std::vector<double> factor(points.size(), 1.);
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_unknown[c] >= 0)
        for (unsigned int q = cell_ranges[c].first; q < cell_ranges[c].second;
             ++q)
          {
            const unsigned int n =
              condition_values(conditions[c], points[q], index, value);
            for (unsigned int k = 0; k < n; ++k)
              factor[q] += lambda[index[k]] * value[k];
            if (!(factor[q] > 0.5 && factor[q] < 1.5))
              return 1.;
          }
    for (unsigned int q = 0; q < points.size(); ++q)
      points[q].weight *= factor[q];

    // The remaining error, relative to the faces' areas.
    std::fill(rhs.begin(), rhs.end(), 0.);
    for (unsigned int f = 0; f < faces.size(); ++f)
      for (unsigned int r = 0; r < 3; ++r)
        rhs[n_unknowns - 3 * faces.size() + 3 * f + r] = faces[f].integrals[r];
    for (unsigned int c = 0; c < n_cells; ++c)
      if (cell_unknown[c] >= 0)
        rhs[cell_unknown[c]] = cell_areas[c];
    subtract_integrals();
    double error = 0;
    for (unsigned int f = 0; f < faces.size(); ++f)
      {
        double area = 0;
        for (const unsigned int c : faces[f].cells)
          area += cell_areas[c];
        for (unsigned int r = 0; r < 3; ++r)
          error =
            std::max(error,
                     std::abs(rhs[n_unknowns - 3 * faces.size() + 3 * f + r]) /
                       area);
      }
    return error;
  }
} // namespace TKR::Mortar
