// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/output/vtu_output.h>

#include <fstream>

namespace TKR::Output
{
  VtuSeries::VtuSeries(const std::string &directory,
                       const std::string &name,
                       const MPI_Comm     mpi_communicator)
    : directory(directory)
    , name(name)
    , mpi_communicator(mpi_communicator)
  {}

  void
  VtuSeries::write(const dealii::DataOut<3> &data_out,
                   const unsigned int        index,
                   const double              time)
  {
    const std::string pvtu =
      data_out.write_vtu_with_pvtu_record(directory + "/",
                                          name,
                                          index,
                                          mpi_communicator,
                                          4);
    records.emplace_back(time, pvtu);
    if (dealii::Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      {
        std::ofstream pvd(directory + "/" + name + ".pvd");
        dealii::DataOutBase::write_pvd_record(pvd, records);
      }
  }
} // namespace TKR::Output
