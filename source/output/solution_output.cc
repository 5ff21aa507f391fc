// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/lac/vector.h>

#include <tkr/elasticity/stress_postprocessor.h>
#include <tkr/output/solution_output.h>

namespace TKR::Output
{
  using namespace dealii;

  void
  report_mesh(const ConditionalOStream   &out,
              Summary                    &summary,
              const Mesh::MeshStatistics &statistics,
              const std::string          &filename,
              const double                quality_warning,
              const bool                  testing)
  {
    const std::string file =
      testing ? filename.substr(filename.rfind('/') + 1) : filename;
    out << "Mesh <" << file << ">: " << statistics.femur_cells << " femur + "
        << statistics.tibia_cells << " tibia cells, " << statistics.n_vertices
        << " vertices" << std::endl
        << "  femur volume " << statistics.femur_volume
        << " mm^3, tibia volume " << statistics.tibia_volume << " mm^3"
        << std::endl;
    for (const types::boundary_id id : {Mesh::BoundaryIds::femur_contact,
                                        Mesh::BoundaryIds::femur_fixation,
                                        Mesh::BoundaryIds::tibia_contact,
                                        Mesh::BoundaryIds::tibia_inferior})
      out << "  " << Mesh::boundary_name(id) << ": "
          << statistics.boundary_area[id] << " mm^2" << std::endl;
    const double tibia_quality =
      statistics.min_quality[Mesh::BoundaryIds::tibia_contact];
    const double femur_quality =
      statistics.min_quality[Mesh::BoundaryIds::femur_contact];
    out << "  cells at the contact surfaces: smallest scaled Jacobian "
        << tibia_quality << " (tibia_contact), " << femur_quality
        << " (femur_contact)" << std::endl;
    // The pressures and the wear depth are nodal values on tibia_contact
    // (the mortar's slave side): its cells decide how they scatter. The
    // femur's cells enter through the projected gap only; on mesh-implant's
    // output (femur 0.26, tibia 0.51) the peak pressure at 2000 N is within
    // 6 % of the structured mesh's (doc/geometry.md), so for them a note.
    if (tibia_quality < quality_warning)
      out << "Warning: cells with a face on tibia_contact have a scaled "
             "Jacobian down to "
          << tibia_quality << ", below the Mesh/Contact cell quality of "
          << quality_warning
          << ": nodal contact pressures and the wear depth scatter on such "
             "cells (doc/geometry.md); mesh the articular surfaces with "
             "shape-regular hexahedra."
          << std::endl;
    if (femur_quality < quality_warning)
      out << "Note: cells with a face on femur_contact have a scaled "
             "Jacobian down to "
          << femur_quality << ", below the Mesh/Contact cell quality of "
          << quality_warning
          << "; they shape the gap the tibia's nodes see: compare the peak "
             "pressure with a finer mesh (doc/geometry.md)."
          << std::endl;
    summary.set("contact_cell_quality_tibia", tibia_quality);
    summary.set("contact_cell_quality_femur", femur_quality);
    summary.set("cells", statistics.femur_cells + statistics.tibia_cells);
    summary.set("femur_volume_mm3", statistics.femur_volume);
    summary.set("tibia_volume_mm3", statistics.tibia_volume);
  }

  void
  finish_run(Summary                  &summary,
             const std::string        &directory,
             const MPI_Comm            mpi_communicator,
             const double              wall_time,
             const bool                testing,
             const ConditionalOStream &out)
  {
    summary.set("mpi_ranks", Utilities::MPI::n_mpi_processes(mpi_communicator));
    if (!testing)
      summary.set("wall_time_s", wall_time);
    summary.write(directory, mpi_communicator);
    out << "Results in <" << directory << "/>" << std::endl;
  }

  VertexFields::VertexFields(const Triangulation<3> &triangulation)
    : fe(1)
    , dof_handler(triangulation)
  {
    dof_handler.distribute_dofs(fe);
    dof_of_vertex.assign(triangulation.n_vertices(),
                         numbers::invalid_dof_index);
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const auto v : cell->vertex_indices())
        dof_of_vertex[cell->vertex_index(v)] = cell->vertex_dof_index(v, 0);
  }

  void
  VertexFields::add(const std::string &name, const std::vector<double> &values)
  {
    AssertDimension(values.size(), dof_of_vertex.size());
    Vector<double> field(dof_handler.n_dofs());
    for (unsigned int v = 0; v < values.size(); ++v)
      if (dof_of_vertex[v] != numbers::invalid_dof_index)
        field(dof_of_vertex[v]) = values[v];
    fields.emplace_back(name, std::move(field));
  }

  void
  VertexFields::add(const SurfaceFields &surface_fields)
  {
    AssertDimension(surface_fields.names.size(), surface_fields.values.size());
    const auto &nodes = surface_fields.surface->nodes();
    for (unsigned int i = 0; i < surface_fields.names.size(); ++i)
      {
        std::vector<double> values(dof_of_vertex.size(), 0.);
        const auto         &field = surface_fields.values[i];
        for (unsigned int j = 0; j < field.size(); ++j)
          values[nodes[j].vertex] = field[j];
        add(surface_fields.names[i], values);
      }
  }

  void
  VertexFields::attach(DataOut<3> &data_out) const
  {
    for (const auto &[name, field] : fields)
      data_out.add_data_vector(
        dof_handler,
        field,
        name,
        {DataComponentInterpretation::component_is_scalar});
  }

  void
  write_solution(const Elasticity::LinearElasticity      &elasticity,
                 const TrilinosWrappers::MPI::Vector     &solution,
                 const Mapping<3>                        &mapping,
                 VtuSeries                               &series,
                 const unsigned int                       index,
                 const double                             time,
                 const std::vector<SurfaceFields>        &surface_fields,
                 const std::function<void(DataOut<3> &)> &add_fields)
  {
    const auto &dof_handler   = elasticity.get_dof_handler();
    const auto &triangulation = dof_handler.get_triangulation();

    DataOut<3> data_out;
    data_out.attach_dof_handler(dof_handler);
    data_out.add_data_vector(
      solution,
      std::vector<std::string>(3, "displacement"),
      DataOut<3>::type_dof_data,
      std::vector<DataComponentInterpretation::DataComponentInterpretation>(
        3,
        DataComponentInterpretation::component_is_part_of_vector));
    const Elasticity::StressPostprocessor   stress(elasticity.get_materials());
    const Elasticity::VonMisesPostprocessor von_mises(
      elasticity.get_materials());
    data_out.add_data_vector(solution, stress);
    data_out.add_data_vector(solution, von_mises);

    Vector<float> material(triangulation.n_active_cells());
    Vector<float> subdomain(triangulation.n_active_cells());
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        material(cell->active_cell_index())  = cell->material_id();
        subdomain(cell->active_cell_index()) = cell->subdomain_id();
      }
    data_out.add_data_vector(material, "material_id");
    data_out.add_data_vector(subdomain, "subdomain");
    // DataOut keeps references: the fields live until the patches are
    // built.
    VertexFields vertex_fields(triangulation);
    for (const auto &fields : surface_fields)
      vertex_fields.add(fields);
    vertex_fields.attach(data_out);
    if (add_fields)
      add_fields(data_out);
    data_out.build_patches(mapping, dof_handler.get_fe().degree);
    series.write(data_out, index, time);
  }
} // namespace TKR::Output
