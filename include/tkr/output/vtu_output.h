// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_output_vtu_output_h
#define tkr_output_vtu_output_h

#include <deal.II/base/mpi.h>

#include <deal.II/numerics/data_out.h>

#include <string>
#include <utility>
#include <vector>

namespace TKR::Output
{
  /**
   * Writes the VTU pieces of a series of outputs (one per rank, with a
   * .pvtu record) and keeps the `.pvd` record of the whole series up to
   * date, so that ParaView opens `NAME.pvd` as a time series (step-18/40).
   */
  class VtuSeries
  {
  public:
    VtuSeries(const std::string &directory,
              const std::string &name,
              const MPI_Comm     mpi_communicator);

    /**
     * Write the patches of @p data_out (build_patches() already called) as
     * output number @p index at time (or step, cycle) @p time.
     */
    void
    write(const dealii::DataOut<3> &data_out,
          const unsigned int        index,
          const double              time);

  private:
    const std::string                           directory;
    const std::string                           name;
    const MPI_Comm                              mpi_communicator;
    std::vector<std::pair<double, std::string>> records;
  };
} // namespace TKR::Output

#endif
