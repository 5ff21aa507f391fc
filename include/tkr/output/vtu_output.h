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
   *
   * Where several groups of ranks write outputs of the same series (the
   * step groups of a gait cycle, each writing its own steps), each group
   * writes its pieces on its @p piece_communicator, and the `.pvd` record
   * of all of them is written by write_record() on the
   * @p record_communicator that joins the groups.
   */
  class VtuSeries
  {
  public:
    /**
     * A series `directory/name.pvd` whose pieces are written on
     * @p piece_communicator; with a @p record_communicator, the `.pvd`
     * file is only written by write_record().
     */
    VtuSeries(const std::string &directory,
              const std::string &name,
              const MPI_Comm     piece_communicator,
              const MPI_Comm     record_communicator = MPI_COMM_NULL);

    /**
     * Write the patches of @p data_out (build_patches() already called) as
     * output number @p index at time (or step, cycle) @p time, compressed
     * by zlib's fastest level (deal.II's default, its best compression,
     * took most of the output's time; doc/performance.md).
     */
    void
    write(dealii::DataOut<3> &data_out,
          const unsigned int  index,
          const double        time);

    /**
     * Collect the outputs written by all groups and write the `.pvd`
     * record of all of them (collective on the record communicator).
     */
    void
    write_record();

  private:
    const std::string                           directory;
    const std::string                           name;
    const MPI_Comm                              piece_communicator;
    const MPI_Comm                              record_communicator;
    std::vector<std::pair<double, std::string>> records;
  };
} // namespace TKR::Output

#endif
