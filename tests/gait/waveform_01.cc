// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Waveform: values at the table rows, linear interpolation between them,
// periodic wrap-around between the last row and 100 %, columns found by
// their names (any order, extra columns ignored), messages for bad tables
// (a missing column, no header, a table that stops before the end of the
// cycle); and the shipped reconstruction data/iso14243-1.csv stays within
// the published values (first 14 % exact) and ranges.

#include <tkr/base/exceptions.h>
#include <tkr/gait/waveform.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "../tests.h"

namespace
{
  const std::vector<std::string> channels = {"flexion_deg",
                                             "axial_force_N",
                                             "ap_force_N",
                                             "ie_torque_Nm"};
  const std::string header = "percent_cycle,flexion_deg,axial_force_N,"
                             "ap_force_N,ie_torque_Nm\n";

  void
  print(const double percent, const std::vector<double> &v)
  {
    deallog << percent << " %: " << v[0] << ' ' << v[1] << ' ' << v[2] << ' '
            << v[3] << std::endl;
  }

  void
  expect_error(const std::string &name, const std::string &text)
  {
    {
      std::ofstream out(name);
      out << text;
    }
    try
      {
        TKR::Gait::Waveform waveform(name, channels);
        deallog << name << ": read (unexpected)" << std::endl;
      }
    catch (const TKR::ExcInputError &exc)
      {
        deallog << TKR::exception_message(exc) << std::endl;
      }
  }
} // namespace

int
main()
{
  initlog();
  {
    std::ofstream out("small.csv");
    out << "# a comment\npercent_cycle,flexion_deg,axial_force_N,ap_force_N,"
           "ie_torque_Nm\n0,0,100,10,1\n25,20,1100,-10,2\n50,40,600,0,0\n"
           "100,0,100,10,1\n";
  }
  const TKR::Gait::Waveform small("small.csv", channels);
  deallog << "rows: " << small.n_rows() << std::endl;
  for (const double p :
       {0., 25., 50., 12.5, 37.5, 75., 99., 100., 112.5, -12.5})
    print(p - 100. * std::floor(p / 100.), small.at(p));

  // The same table with its columns in another order and one more column.
  {
    std::ofstream out("shuffled.csv");
    out << "ie_torque_Nm,percent_cycle,temperature_C,axial_force_N,"
           "flexion_deg,ap_force_N\n1,0,37,100,0,10\n2,25,37,1100,20,-10\n"
           "0,50,37,600,40,0\n1,100,37,100,0,10\n";
  }
  const TKR::Gait::Waveform shuffled("shuffled.csv", channels);
  bool                      same = true;
  for (const double p : {0., 12.5, 37.5, 75., 99.})
    same = same && shuffled.at(p) == small.at(p);
  deallog << "columns by name, any order, extra ones ignored: " << yes_no(same)
          << std::endl;

  expect_error("decreasing.csv",
               header + "0,0,0,0,0\n30,1,1,1,1\n20,1,1,1,1\n");
  expect_error("columns.csv", header + "0,0,0,0,0\n30,1,1,1\n");
  expect_error("start.csv", header + "5,0,0,0,0\n30,1,1,1,1\n");
  expect_error("periodic.csv", header + "0,0,0,0,0\n30,1,1,1,1\n100,2,0,0,0\n");
  expect_error("missing.csv",
               "percent_cycle,flexion_deg,axial_force_N,ap_force_N\n"
               "0,0,0,0\n50,1,1,1\n100,0,0,0\n");
  expect_error("no_header.csv", "0,0,0,0,0\n50,1,1,1,1\n100,0,0,0,0\n");
  // Rows every 1 % up to 50 %: half of the cycle is missing.
  {
    std::string half = header;
    for (unsigned int p = 0; p <= 50; ++p)
      half += std::to_string(p) + ",1,100,0,0\n";
    expect_error("half.csv", half);
  }

  const TKR::Gait::Waveform iso(std::string(SOURCE_DIR) +
                                  "/../../data/iso14243-1.csv",
                                channels);
  const double              published[15][2] = {{0, 167.6},
                                                {0.17, 597.5},
                                                {0.69, 1457.4},
                                                {1.53, 1887.3},
                                                {2.65, 1782.9},
                                                {4, 1530.9},
                                                {5.53, 1278.8},
                                                {7.16, 1174.6},
                                                {8.84, 1270.1},
                                                {10.47, 1530.9},
                                                {12, 1887.3},
                                                {13.35, 2243.6},
                                                {14.47, 2504.5},
                                                {15.31, 2600},
                                                {15.83, 2570}};
  bool                      first_14         = true;
  for (unsigned int p = 0; p < 15; ++p)
    first_14 = first_14 && iso.at(p)[0] == published[p][0] &&
               iso.at(p)[1] == published[p][1];
  double min[4] = {1e9, 1e9, 1e9, 1e9}, max[4] = {-1e9, -1e9, -1e9, -1e9};
  for (unsigned int p = 0; p < 100; ++p)
    {
      const auto v = iso.at(p);
      for (unsigned int c = 0; c < 4; ++c)
        {
          min[c] = std::min(min[c], v[c]);
          max[c] = std::max(max[c], v[c]);
        }
    }
  deallog << "ISO reconstruction: rows " << iso.n_rows()
          << ", first 14 % as published: " << yes_no(first_14) << std::endl;
  deallog << "flexion " << min[0] << " .. " << max[0] << " deg" << std::endl;
  deallog << "axial force " << min[1] << " .. " << max[1] << " N" << std::endl;
  deallog << "AP force " << min[2] << " .. " << max[2] << " N" << std::endl;
  deallog << "IE torque " << min[3] << " .. " << max[3] << " N m" << std::endl;
}
