// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_output_solution_output_h
#define tkr_output_solution_output_h

#include <deal.II/base/conditional_ostream.h>

#include <deal.II/fe/mapping.h>

#include <deal.II/numerics/data_out.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mesh/mesh.h>
#include <tkr/mortar/contact_surface.h>
#include <tkr/output/summary.h>
#include <tkr/output/vtu_output.h>

#include <functional>
#include <ostream>

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
              const bool                        testing);

  /**
   * Up to three scalar fields given per node of a contact surface (e.g.
   * pressure, gap, active flag) and their names, for write_solution().
   */
  struct SurfaceFields
  {
    const Mortar::ContactSurface    *surface;
    std::vector<std::string>         names;
    std::vector<std::vector<double>> values;
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
   * Write the displacement, the stress tensor, the von Mises stress, the
   * material id and the MPI partition of @p elasticity as output @p index
   * of @p series, with the @p surface_fields (stored in the displacement
   * components of vectors on the same DoFHandler, zero away from their
   * surface); @p add_fields may attach further data vectors before the
   * patches are built.
   */
  void
  write_solution(
    const Elasticity::LinearElasticity              &elasticity,
    const dealii::Mapping<3>                        &mapping,
    VtuSeries                                       &series,
    const unsigned int                               index,
    const double                                     time,
    const std::vector<SurfaceFields>                &surface_fields = {},
    const std::function<void(dealii::DataOut<3> &)> &add_fields     = {});
} // namespace TKR::Output

#endif
