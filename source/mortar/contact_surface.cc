// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/geometry_info.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe.h>

#include <tkr/base/exceptions.h>
#include <tkr/mortar/contact_surface.h>
#include <tkr/mortar/surface_geometry.h>

#include <algorithm>
#include <map>

namespace TKR::Mortar
{
  using namespace dealii;

  ContactSurface::ContactSurface(const DoFHandler<3>     &dof_handler,
                                 const types::boundary_id boundary_id)
  {
    AssertThrow(dof_handler.get_fe().degree == 1,
                ExcInputError("Contact needs Finite element degree = 1 "
                              "(the mortar coupling is implemented for "
                              "bilinear faces)."));
    std::map<unsigned int, unsigned int> node_of_vertex;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            cell->face(f)->boundary_id() == boundary_id)
          {
            const auto face = cell->face(f);
            Face       entry;
            for (unsigned int v = 0; v < 4; ++v)
              {
                const unsigned int vertex = face->vertex_index(v);
                const auto [it, inserted] =
                  node_of_vertex.emplace(vertex, node_list.size());
                if (inserted)
                  {
                    Node node;
                    node.vertex = vertex;
                    for (unsigned int c = 0; c < 3; ++c)
                      node.dofs[c] = face->vertex_dof_index(v, c);
                    node_list.push_back(node);
                  }
                entry.nodes[v] = it->second;
              }
            for (unsigned int v = 0; v < 8; ++v)
              entry.cell_vertices[v] = cell->vertex_index(v);
            face_list.push_back(entry);
          }

    faces_of_node.resize(node_list.size());
    for (unsigned int f = 0; f < face_list.size(); ++f)
      for (const unsigned int n : face_list[f].nodes)
        faces_of_node[n].push_back(f);
  }

  ContactSurface
  ContactSurface::with_dofs_of(const DoFHandler<3> &dof_handler) const
  {
    AssertThrow(dof_handler.get_fe().degree == 1,
                ExcInputError("Contact needs Finite element degree = 1 "
                              "(the mortar coupling is implemented for "
                              "bilinear faces)."));
    ContactSurface                       surface = *this;
    std::map<unsigned int, unsigned int> node_of_vertex;
    for (unsigned int j = 0; j < node_list.size(); ++j)
      node_of_vertex[node_list[j].vertex] = j;
    std::vector<bool> found(node_list.size(), false);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          for (const auto v : cell->face(f)->vertex_indices())
            {
              const auto it =
                node_of_vertex.find(cell->face(f)->vertex_index(v));
              if (it == node_of_vertex.end() || found[it->second])
                continue;
              for (unsigned int c = 0; c < 3; ++c)
                surface.node_list[it->second].dofs[c] =
                  cell->face(f)->vertex_dof_index(v, c);
              found[it->second] = true;
            }
    AssertThrow(std::all_of(found.begin(),
                            found.end(),
                            [](bool b) { return b; }),
                ExcInternalError());
    return surface;
  }

  // phi_j integrated over the faces around node j with the face's area
  // element |dA| and its area normal dA (outward: the sign of
  // orientation()).
  ContactSurface::NodalMeasures
  ContactSurface::nodal_measures(const std::vector<Point<3>> &positions) const
  {
    NodalMeasures measures;
    measures.area.assign(node_list.size(), 0.);
    measures.normal.assign(node_list.size(), Tensor<1, 3>());
    const QGauss<2> face_quadrature(2);
    for (unsigned int e = 0; e < face_list.size(); ++e)
      {
        const BilinearQuad quad{face_vertices(e, positions)};
        const double       sign = orientation(e, positions);
        for (unsigned int q = 0; q < face_quadrature.size(); ++q)
          {
            const auto N = BilinearQuad::shape_values(face_quadrature.point(q));
            const Tensor<1, 3> dA = sign *
                                    quad.area_normal(face_quadrature.point(q)) *
                                    face_quadrature.weight(q);
            for (unsigned int i = 0; i < 4; ++i)
              {
                const unsigned int j = face_list[e].nodes[i];
                measures.area[j] += N[i] * dA.norm();
                measures.normal[j] += N[i] * dA;
              }
          }
      }
    for (unsigned int j = 0; j < node_list.size(); ++j)
      {
        measures.normal[j] /= measures.normal[j].norm();
        measures.total_area += measures.area[j];
      }
    return measures;
  }

  std::array<Point<3>, 4>
  ContactSurface::face_vertices(const unsigned int           f,
                                const std::vector<Point<3>> &positions) const
  {
    std::array<Point<3>, 4> x;
    for (unsigned int v = 0; v < 4; ++v)
      x[v] = positions[node_list[face_list[f].nodes[v]].vertex];
    return x;
  }

  double
  ContactSurface::orientation(const unsigned int           f,
                              const std::vector<Point<3>> &positions) const
  {
    const BilinearQuad quad{face_vertices(f, positions)};
    Point<3>           cell_centre;
    for (const unsigned int v : face_list[f].cell_vertices)
      cell_centre += positions[v] / 8.;
    const Point2 centre(0.5, 0.5);
    return (quad.area_normal(centre) * (quad.point(centre) - cell_centre) >=
            0) ?
             1. :
             -1.;
  }
} // namespace TKR::Mortar
