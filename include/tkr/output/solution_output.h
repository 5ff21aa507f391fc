// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_output_solution_output_h
#define tkr_output_solution_output_h

#include <deal.II/base/conditional_ostream.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/mapping.h>

#include <deal.II/lac/vector.h>

#include <deal.II/numerics/data_out.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mesh/mesh.h>
#include <tkr/mortar/contact_surface.h>
#include <tkr/output/summary.h>
#include <tkr/output/vtu_output.h>

#include <functional>
#include <list>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace TKR::Output
{
  /**
   * Print the mesh statistics (cells, vertices, volumes, areas of the
   * tagged surfaces) and record them in @p summary. With @p testing, the
   * file is named without its directory (regression output must not depend
   * on where the sources are).
   */
  void
  report_mesh(const dealii::ConditionalOStream &out,
              Summary                          &summary,
              const Mesh::MeshStatistics       &statistics,
              const std::string                &filename,
              const double                      quality_warning,
              const bool                        testing);

  /**
   * Scalar fields given per node of a contact surface (e.g. pressure, gap,
   * active flag) and their names, one name per field, for
   * write_solution().
   */
  struct SurfaceFields
  {
    const Mortar::ContactSurface    *surface;
    std::vector<std::string>         names;
    std::vector<std::vector<double>> values;
  };

  /**
   * Scalar fields given per triangulation vertex, written by a DataOut as
   * point data of their own names (on a scalar Q1 DoFHandler of their
   * own, so no field needs to fill the components of a vector). Add the
   * fields, then attach() them to a DataOut on the same triangulation;
   * this object must live until the patches are built.
   */
  class VertexFields
  {
  public:
    explicit VertexFields(const dealii::Triangulation<3> &triangulation);

    /** A field of one value per triangulation vertex. */
    void
    add(const std::string &name, const std::vector<double> &values);

    /** The fields of @p surface_fields (zero away from their surface). */
    void
    add(const SurfaceFields &surface_fields);

    /** Add every field to @p data_out (call after the last add()). */
    void
    attach(dealii::DataOut<3> &data_out) const;

  private:
    const dealii::FE_Q<3>                                     fe;
    dealii::DoFHandler<3>                                     dof_handler;
    std::vector<dealii::types::global_dof_index>              dof_of_vertex;
    std::list<std::pair<std::string, dealii::Vector<double>>> fields;
  };

  /**
   * End of a run: record the number of MPI ranks and (unless @p testing)
   * the wall time in @p summary, write `directory/summary.json` and say
   * where the results are.
   */
  void
  finish_run(Summary                          &summary,
             const std::string                &directory,
             const MPI_Comm                    mpi_communicator,
             const double                      wall_time,
             const bool                        testing,
             const dealii::ConditionalOStream &out);

  /**
   * Write the displacement @p solution (ghosted, on the DoFHandler of
   * @p elasticity), the stress tensor, the von Mises stress, the material
   * id and the MPI partition as output @p index of @p series, with the
   * @p surface_fields (point data, zero away from their surface);
   * @p add_fields may attach further data vectors before the patches are
   * built.
   */
  void
  write_solution(
    const Elasticity::LinearElasticity              &elasticity,
    const dealii::TrilinosWrappers::MPI::Vector     &solution,
    const dealii::Mapping<3>                        &mapping,
    VtuSeries                                       &series,
    const unsigned int                               index,
    const double                                     time,
    const std::vector<SurfaceFields>                &surface_fields = {},
    const std::function<void(dealii::DataOut<3> &)> &add_fields     = {});
} // namespace TKR::Output

#endif
