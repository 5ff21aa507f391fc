// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>

#include <deal.II/grid/grid_in.h>

#include <tkr/base/exceptions.h>
#include <tkr/mesh/mesh.h>

#include <fstream>
#include <limits>
#include <map>
#include <sstream>

namespace TKR::Mesh
{
  using namespace dealii;

  std::vector<PhysicalGroup>
  read_physical_names(const std::string &filename)
  {
    std::ifstream in(filename);
    AssertThrow(in.good(),
                ExcInputError("Cannot open the mesh file <" + filename +
                              ">: it does not exist or is not readable."));
    std::vector<PhysicalGroup> groups;
    std::string                line;
    while (std::getline(in, line))
      if (line.rfind("$PhysicalNames", 0) == 0)
        {
          unsigned int n_groups = 0;
          in >> n_groups;
          for (unsigned int i = 0; i < n_groups; ++i)
            {
              PhysicalGroup group;
              in >> group.dim >> group.tag;
              std::getline(in, line);
              const auto first = line.find('"');
              const auto last  = line.rfind('"');
              AssertThrow(in.good() && first != std::string::npos &&
                            last > first,
                          ExcInputError("The $PhysicalNames table of the mesh "
                                        "file <" +
                                        filename + "> is malformed."));
              group.name = line.substr(first + 1, last - first - 1);
              groups.push_back(group);
            }
          break;
        }
    return groups;
  }

  namespace
  {
    /** The groups a mesh must have: name, dimension and the id we give it. */
    struct RequiredGroup
    {
      std::string  name;
      int          dim;
      unsigned int id;
    };

    std::vector<RequiredGroup>
    required_groups(const Parameters::Mesh &parameters)
    {
      return {{parameters.femur_name, 3, MaterialIds::femur},
              {parameters.tibia_name, 3, MaterialIds::tibia},
              {parameters.femur_contact_name, 2, BoundaryIds::femur_contact},
              {parameters.femur_fixation_name, 2, BoundaryIds::femur_fixation},
              {parameters.tibia_contact_name, 2, BoundaryIds::tibia_contact},
              {parameters.tibia_inferior_name, 2, BoundaryIds::tibia_inferior}};
    }

    std::string
    list_groups(const std::vector<PhysicalGroup> &groups)
    {
      if (groups.empty())
        return "none";
      std::string result;
      for (const auto &group : groups)
        result += (result.empty() ? "" : ", ") + ("'" + group.name + "'") +
                  " (dimension " + std::to_string(group.dim) + ")";
      return result;
    }

  } // namespace

  // At vertex v the three edges that leave it, each oriented along its
  // reference direction, span the Jacobian there.
  double
  min_vertex_jacobian(const std::array<Point<3>, 8> &x)
  {
    double min_det = std::numeric_limits<double>::max();
    for (unsigned int v = 0; v < 8; ++v)
      {
        Tensor<1, 3> edge[3];
        for (unsigned int d = 0; d < 3; ++d)
          {
            const unsigned int bit = 1u << d;
            edge[d]                = x[v | bit] - x[v & ~bit];
          }
        min_det =
          std::min(min_det, edge[0] * cross_product_3d(edge[1], edge[2]));
      }
    return min_det;
  }

  double
  min_scaled_jacobian(const std::array<Point<3>, 8> &x)
  {
    double min_ratio = std::numeric_limits<double>::max();
    for (unsigned int v = 0; v < 8; ++v)
      {
        Tensor<1, 3> edge[3];
        for (unsigned int d = 0; d < 3; ++d)
          {
            const unsigned int bit = 1u << d;
            edge[d]                = x[v | bit] - x[v & ~bit];
          }
        const double lengths = edge[0].norm() * edge[1].norm() * edge[2].norm();
        min_ratio =
          std::min(min_ratio,
                   lengths > 0 ?
                     edge[0] * cross_product_3d(edge[1], edge[2]) / lengths :
                     0.);
      }
    return min_ratio;
  }

  std::string
  boundary_name(const types::boundary_id id)
  {
    switch (id)
      {
        case BoundaryIds::femur_contact:
          return "femur_contact";
        case BoundaryIds::femur_fixation:
          return "femur_fixation";
        case BoundaryIds::tibia_contact:
          return "tibia_contact";
        case BoundaryIds::tibia_inferior:
          return "tibia_inferior";
        default:
          return "free surface";
      }
  }

  // GridIn stores the numeric gmsh tags of the physical volumes as material
  // ids and those of the physical surfaces as boundary ids. We translate the
  // configured group names to those tags with the $PhysicalNames table, then
  // renumber to the fixed ids of MaterialIds and BoundaryIds. Faces in no
  // (or in another) physical surface become traction-free.
  void
  read_mesh(const Parameters::Mesh &parameters, Triangulation<3> &triangulation)
  {
    const std::string &filename = parameters.file;
    const auto         groups   = read_physical_names(filename);

    std::map<int, unsigned int> volume_ids, surface_ids;
    std::string                 missing;
    for (const auto &required : required_groups(parameters))
      {
        bool found = false;
        for (const auto &group : groups)
          if (group.name == required.name && group.dim == required.dim)
            {
              (required.dim == 3 ? volume_ids : surface_ids)[group.tag] =
                required.id;
              found = true;
            }
        if (!found)
          missing += (missing.empty() ? "'" : ", '") + required.name + "'" +
                     " (dimension " + std::to_string(required.dim) + ")";
      }
    AssertThrow(missing.empty(),
                ExcInputError("The mesh file <" + filename +
                              "> lacks the physical group(s) " + missing +
                              ". Groups found: " + list_groups(groups) +
                              ". Rename them in gmsh or set the group names "
                              "in 'subsection Mesh'."));

    try
      {
        GridIn<3> grid_in;
        grid_in.attach_triangulation(triangulation);
        std::ifstream in(filename);
        grid_in.read_msh(in);
      }
    catch (const ExceptionBase &exc)
      {
        AssertThrow(false,
                    ExcInputError("Cannot read the mesh file <" + filename +
                                  ">: " + exception_message(exc)));
      }

    for (const auto &cell : triangulation.active_cell_iterators())
      {
        const auto volume = volume_ids.find(cell->material_id());
        AssertThrow(volume != volume_ids.end(),
                    ExcInputError(
                      "The mesh file <" + filename + "> has a cell (centre " +
                      Utilities::to_string(cell->center()[0]) + ", " +
                      Utilities::to_string(cell->center()[1]) + ", " +
                      Utilities::to_string(cell->center()[2]) +
                      ") in the physical volume with tag " +
                      std::to_string(cell->material_id()) +
                      ", which is "
                      "neither '" +
                      parameters.femur_name + "' nor '" +
                      parameters.tibia_name + "'."));
        cell->set_material_id(volume->second);
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              const auto surface = surface_ids.find(face->boundary_id());
              face->set_boundary_id(surface != surface_ids.end() ?
                                      surface->second :
                                      BoundaryIds::free);
            }
      }

    check_mesh(triangulation, filename);
  }

  void
  check_mesh(const Triangulation<3> &triangulation, const std::string &filename)
  {
    AssertThrow(triangulation.all_reference_cells_are_hyper_cube(),
                ExcInputError("The mesh file <" + filename +
                              "> contains cells that are not hexahedra; "
                              "tkr-wear needs an all-hexahedral mesh."));

    // A valid hexahedron has a positive Jacobian determinant at all eight
    // vertices. GridIn turns cells with negative volume around, so what can
    // remain are twisted or collapsed cells; deal.II cannot integrate on
    // those.
    unsigned int n_bad = 0;
    std::string  first_bad;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        std::array<Point<3>, 8> x;
        for (unsigned int v = 0; v < 8; ++v)
          x[v] = cell->vertex(v);
        const double min_det = min_vertex_jacobian(x);
        const double scale   = std::pow(cell->diameter(), 3);
        if (min_det <= 1e-12 * scale)
          {
            if (n_bad == 0)
              {
                std::ostringstream out;
                out << "cell " << cell->active_cell_index() << " of the "
                    << (cell->material_id() == MaterialIds::femur ? "femur" :
                                                                    "tibia")
                    << " (centre " << cell->center() << ") has Jacobian "
                    << "determinant " << min_det / scale
                    << " x diameter^3 at a vertex";
                first_bad = out.str();
              }
            ++n_bad;
          }
      }
    AssertThrow(n_bad == 0,
                ExcInputError("The mesh file <" + filename + "> has " +
                              std::to_string(n_bad) +
                              " inverted, twisted or degenerate cell(s); " +
                              "the first: " + first_bad + "."));

    // Integrating (below) needs valid cells, so this comes second.
    const MeshStatistics statistics = compute_statistics(triangulation);
    AssertThrow(statistics.femur_cells > 0 && statistics.tibia_cells > 0,
                ExcInputError("The mesh file <" + filename + "> has " +
                              std::to_string(statistics.femur_cells) +
                              " femur and " +
                              std::to_string(statistics.tibia_cells) +
                              " tibia cells; both bodies need cells."));
    for (const types::boundary_id id : {BoundaryIds::femur_contact,
                                        BoundaryIds::femur_fixation,
                                        BoundaryIds::tibia_contact,
                                        BoundaryIds::tibia_inferior})
      AssertThrow(statistics.boundary_area[id] > 0,
                  ExcInputError("The mesh file <" + filename +
                                "> has no boundary face in the physical "
                                "surface '" +
                                boundary_name(id) +
                                "' (the group exists but is empty, or its "
                                "faces are not on the boundary)."));
  }

  std::vector<bool>
  material_vertices(const Triangulation<3>  &triangulation,
                    const types::material_id material_id)
  {
    std::vector<bool> result(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->material_id() == material_id)
        for (const auto v : cell->vertex_indices())
          result[cell->vertex_index(v)] = true;
    return result;
  }

  MeshStatistics
  compute_statistics(const Triangulation<3> &triangulation)
  {
    MeshStatistics statistics;
    statistics.n_vertices = triangulation.n_used_vertices();

    const FE_Q<3>      fe(1);
    const MappingQ1<3> mapping;
    FEValues<3>        fe_values(mapping, fe, QGauss<3>(2), update_JxW_values);
    FEFaceValues<3>    fe_face_values(mapping,
                                   fe,
                                   QGauss<2>(3),
                                   update_JxW_values);
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        fe_values.reinit(cell);
        double volume = 0;
        for (const double JxW : fe_values.get_JxW_values())
          volume += JxW;
        if (cell->material_id() == MaterialIds::femur)
          {
            statistics.femur_volume += volume;
            ++statistics.femur_cells;
          }
        else
          {
            statistics.tibia_volume += volume;
            ++statistics.tibia_cells;
          }
        std::array<Point<3>, 8> x;
        for (const auto v : cell->vertex_indices())
          x[v] = cell->vertex(v);
        const double quality = min_scaled_jacobian(x);
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() < 5)
            {
              const auto id = cell->face(f)->boundary_id();
              fe_face_values.reinit(cell, f);
              for (const double JxW : fe_face_values.get_JxW_values())
                statistics.boundary_area[id] += JxW;
              statistics.min_quality[id] =
                std::min(statistics.min_quality[id], quality);
            }
      }
    return statistics;
  }
} // namespace TKR::Mesh
