// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/atomic_file.h>
#include <tkr/output/vtu_output.h>

#include <algorithm>
#include <sstream>

namespace TKR::Output
{
  using namespace dealii;

  VtuSeries::VtuSeries(const std::string &directory,
                       const std::string &name,
                       const MPI_Comm     piece_communicator,
                       const MPI_Comm     record_communicator)
    : directory(directory)
    , name(name)
    , piece_communicator(piece_communicator)
    , record_communicator(record_communicator)
  {}

  void
  VtuSeries::write(DataOut<3>        &data_out,
                   const unsigned int index,
                   const double       time)
  {
    DataOutBase::VtkFlags flags;
    flags.compression_level = DataOutBase::VtkFlags::best_speed;
    data_out.set_flags(flags);
    const std::string pvtu =
      data_out.write_vtu_with_pvtu_record(directory + "/",
                                          name,
                                          index,
                                          piece_communicator,
                                          4);
    records.emplace_back(time, pvtu);
    if (record_communicator == MPI_COMM_NULL &&
        Utilities::MPI::this_mpi_process(piece_communicator) == 0)
      {
        std::ostringstream pvd;
        DataOutBase::write_pvd_record(pvd, records);
        write_atomically(directory + "/" + name + ".pvd", pvd.str());
      }
  }

  void
  VtuSeries::write_record()
  {
    Assert(record_communicator != MPI_COMM_NULL,
           ExcMessage("This series writes its record in write()."));
    // Only the group roots' records count (every rank of a group has the
    // same ones).
    const bool is_group_root =
      Utilities::MPI::this_mpi_process(piece_communicator) == 0;
    std::vector<std::pair<double, std::string>> all;
    for (const auto &from_rank :
         Utilities::MPI::all_gather(record_communicator,
                                    is_group_root ? records :
                                                    decltype(records)()))
      all.insert(all.end(), from_rank.begin(), from_rank.end());
    std::sort(all.begin(), all.end());
    if (Utilities::MPI::this_mpi_process(record_communicator) == 0)
      {
        std::ostringstream pvd;
        DataOutBase::write_pvd_record(pvd, all);
        write_atomically(directory + "/" + name + ".pvd", pvd.str());
      }
  }
} // namespace TKR::Output
