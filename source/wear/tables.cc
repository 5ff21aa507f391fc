// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/csv_table.h>
#include <tkr/base/exceptions.h>
#include <tkr/wear/tables.h>

#include <algorithm>

namespace TKR::Wear
{
  using namespace dealii;

  PiecewiseLinear::PiecewiseLinear(std::vector<double> x, std::vector<double> y)
    : xs(std::move(x))
    , ys(std::move(y))
  {
    AssertDimension(xs.size(), ys.size());
    Assert(!xs.empty(),
           ExcMessage("A piecewise linear function needs a point."));
    for (unsigned int i = 1; i < xs.size(); ++i)
      Assert(xs[i] > xs[i - 1], ExcMessage("The x values must increase."));
  }

  std::vector<std::pair<double, double>>
  PiecewiseLinear::points() const
  {
    std::vector<std::pair<double, double>> result;
    for (unsigned int i = 0; i < xs.size(); ++i)
      result.emplace_back(xs[i], ys[i]);
    return result;
  }

  double
  PiecewiseLinear::value(const double x) const
  {
    Assert(!xs.empty(), ExcMessage("The function is empty."));
    if (x <= xs.front())
      return ys.front();
    if (x >= xs.back())
      return ys.back();
    const unsigned int i =
      std::upper_bound(xs.begin(), xs.end(), x) - xs.begin() - 1;
    const double s = (x - xs[i]) / (xs[i + 1] - xs[i]);
    return (1 - s) * ys[i] + s * ys[i + 1];
  }

  // The trapezoids of the full intervals before x, the part of the one x
  // lies in, and the constants beyond the ends.
  double
  PiecewiseLinear::primitive(const double x) const
  {
    if (x <= xs.front())
      return (x - xs.front()) * ys.front();
    double       sum = 0;
    unsigned int i   = 0;
    for (; i + 1 < xs.size() && xs[i + 1] <= x; ++i)
      sum += 0.5 * (ys[i] + ys[i + 1]) * (xs[i + 1] - xs[i]);
    return sum + 0.5 * (ys[i] + value(x)) * (x - xs[i]);
  }

  double
  PiecewiseLinear::integral(const double a, const double b) const
  {
    Assert(a <= b, ExcMessage("The integral needs a <= b."));
    return primitive(b) - primitive(a);
  }

  namespace
  {
    /** Refuse a negative value in @p column of @p table. */
    void
    check_non_negative(const CsvTable &table, const std::string &column)
    {
      for (unsigned int r = 0; r < table.n_rows(); ++r)
        AssertThrow(table(r, column) >= 0,
                    ExcInputError(table.where(r) + column +
                                  " must not be negative."));
    }
  } // namespace

  PiecewiseLinear
  read_run_in(const std::string &filename)
  {
    const CsvTable table(filename,
                         "run-in file",
                         {"cycles", "factor"},
                         {},
                         "cycles,factor",
                         "doc/wear.md, Run-in");
    AssertThrow(table.n_rows() > 0,
                ExcInputError(table.name() + " has no rows of data."));
    check_non_negative(table, "cycles");
    check_non_negative(table, "factor");
    std::vector<double> cycles, factor;
    for (unsigned int r = 0; r < table.n_rows(); ++r)
      {
        AssertThrow(r == 0 || table(r, "cycles") > cycles.back(),
                    ExcInputError(table.where(r) + "cycles must increase."));
        cycles.push_back(table(r, "cycles"));
        factor.push_back(table(r, "factor"));
      }
    return PiecewiseLinear(cycles, factor);
  }

  CrossShearTable::CrossShearTable(const std::string         &filename,
                                   const std::string         &value_column,
                                   const bool                 with_pressure,
                                   const CrossShearDefinition definition)
    : filename(filename)
  {
    // The cross-shear column names the definition the table was fitted
    // with (doc/wear.md, Cross-shear tables).
    const bool        abs_sin = definition == CrossShearDefinition::abs_sin;
    const std::string column  = abs_sin ? "cross_shear_abs_sin" : "cross_shear";
    const std::string other   = abs_sin ? "cross_shear" : "cross_shear_abs_sin";
    const CsvTable    table(filename,
                         "cross-shear table",
                         {value_column},
                         {"cross_shear", "cross_shear_abs_sin", "pressure_MPa"},
                         column + "," + value_column +
                           (with_pressure ? "[,pressure_MPa]" : ""),
                         "doc/wear.md, Cross-shear tables");
    AssertThrow(table.has_column(column) || !table.has_column(other),
                ExcInputError(
                  table.name() + " has the column " + other +
                  ": it was fitted with the " +
                  (abs_sin ? "work-tensor (sin^2)" : "|sin|") +
                  " cross-shear, and this run computes the " +
                  (abs_sin ? "|sin|" : "work-tensor (sin^2)") +
                  " one (Wear/Cross-shear definition = " +
                  (abs_sin ? "abs sin" : "work tensor") +
                  "); a table and the run must use the same definition "
                  "(doc/wear.md, Cross-shear)."));
    AssertThrow(table.has_column(column),
                ExcInputError(table.name() + " has no column " + column +
                              " (the columns: " + column + "," + value_column +
                              "; doc/wear.md, Cross-shear "
                              "tables)."));
    AssertThrow(table.n_rows() > 0,
                ExcInputError(table.name() + " has no rows of data."));
    AssertThrow(with_pressure || !table.has_column("pressure_MPa"),
                ExcInputError(table.name() +
                              " has a column pressure_MPa, but this law's "
                              "coefficient depends on the cross-shear only "
                              "(doc/wear.md)."));
    check_non_negative(table, column);
    // The ratio cannot exceed its definition's largest value (doc/wear.md,
    // Cross-shear): a larger value is a table in another unit (percent),
    // which would otherwise read every node near its first row.
    const double largest = largest_cross_shear(definition);
    for (unsigned int r = 0; r < table.n_rows(); ++r)
      AssertThrow(table(r, column) <= largest * (1 + 1e-12),
                  ExcInputError(
                    table.where(r) + column + " is " +
                    format_number(table(r, column)) +
                    ", but the cross-shear is a ratio from 0 to " +
                    (abs_sin ? "1/sqrt(2) = 0.7071" : "0.5") +
                    " (the frictional work across the principal molecular "
                    "orientation over the total, doc/wear.md); a table in "
                    "percent must be divided by 100."));
    check_non_negative(table, value_column);
    const bool by_pressure = table.has_column("pressure_MPa");
    if (by_pressure)
      check_non_negative(table, "pressure_MPa");
    std::vector<double> cs, values;
    for (unsigned int r = 0; r < table.n_rows(); ++r)
      {
        const double p = by_pressure ? table(r, "pressure_MPa") : 0.;
        if (pressures.empty() || p != pressures.back())
          {
            AssertThrow(pressures.empty() || p > pressures.back(),
                        ExcInputError(table.where(r) +
                                      "pressure_MPa must increase from one "
                                      "block of rows to the next (the rows "
                                      "of each pressure together)."));
            if (!pressures.empty())
              of_cross_shear.emplace_back(cs, values);
            pressures.push_back(p);
            cs.clear();
            values.clear();
          }
        AssertThrow(cs.empty() || table(r, column) > cs.back(),
                    ExcInputError(table.where(r) +
                                  "cross_shear must increase within the "
                                  "rows of one pressure."));
        cs.push_back(table(r, column));
        values.push_back(table(r, value_column));
      }
    of_cross_shear.emplace_back(cs, values);
  }

  double
  CrossShearTable::value(const double cs, const double p) const
  {
    if (p <= pressures.front())
      return of_cross_shear.front().value(cs);
    if (p >= pressures.back())
      return of_cross_shear.back().value(cs);
    const unsigned int i =
      std::upper_bound(pressures.begin(), pressures.end(), p) -
      pressures.begin() - 1;
    const double s = (p - pressures[i]) / (pressures[i + 1] - pressures[i]);
    return (1 - s) * of_cross_shear[i].value(cs) +
           s * of_cross_shear[i + 1].value(cs);
  }
} // namespace TKR::Wear
