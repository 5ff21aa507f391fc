// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/elasticity/direct_solver.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_MpiComm.h>
#include <mpi.h>
#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <memory>
#include <thread>
#include <utility>
#include <vector>

#include "cholmod_block.h"

namespace TKR::Elasticity
{
  using internal::Index;
  using internal::OpenBlasThreads;
  using internal::ScopedBlasThreads;

  namespace
  {
    MPI_Comm
    communicator_of(const Epetra_BlockMap &map)
    {
      const auto *comm = dynamic_cast<const Epetra_MpiComm *>(&map.Comm());
      return comm != nullptr ? comm->Comm() : MPI_COMM_SELF;
    }

    /** Ranks of MPI_COMM_WORLD on this node, without a collective call. */
    unsigned int
    ranks_on_this_node()
    {
      for (const char *variable :
           {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"})
        if (const char *value = std::getenv(variable))
          return std::max(1, std::atoi(value));
      // Unknown launcher: assume all ranks share this node (never too many
      // threads).
      int n_ranks = 1;
      MPI_Comm_size(MPI_COMM_WORLD, &n_ranks);
      return n_ranks;
    }
    /**
     * The block of each row of a symmetric matrix (row i's entries: the
     * columns @p columns from @p first_entry[i] on, @p n_entries[i] of
     * them): the connected components of its graph (union-find), the
     * largest first; all but the seven largest form the eighth. -1 for a
     * row with only its diagonal entry. @p n_blocks gets their number.
     */
    std::vector<int>
    blocks_of_rows(const std::vector<int>         &n_entries,
                   const std::vector<std::size_t> &first_entry,
                   const std::vector<long long>   &columns,
                   unsigned int                   &n_blocks)
    {
      const long long        n = n_entries.size();
      std::vector<long long> parent(n);
      const auto             root = [&parent](long long i) {
        while (parent[i] != i)
          i = parent[i] = parent[parent[i]];
        return i;
      };
      for (long long i = 0; i < n; ++i)
        parent[i] = i;
      std::vector<bool> coupled(n, false);
      for (long long i = 0; i < n; ++i)
        for (int k = 0; k < n_entries[i]; ++k)
          {
            const long long j = columns[first_entry[i] + k];
            if (j != i)
              {
                coupled[i] = coupled[j] = true;
                const long long a = root(i), b = root(j);
                if (a != b)
                  parent[std::max(a, b)] = std::min(a, b);
              }
          }

      // the components (by their root, the smallest row), largest first
      std::vector<long long> size(n, 0), components;
      for (long long i = 0; i < n; ++i)
        if (coupled[i])
          ++size[root(i)];
      for (long long i = 0; i < n; ++i)
        if (size[i] > 0)
          components.push_back(i);
      std::stable_sort(components.begin(),
                       components.end(),
                       [&size](const long long a, const long long b) {
                         return size[a] > size[b];
                       });
      constexpr unsigned int max_blocks = 8;
      std::vector<int>       block_of_root(n, -1);
      for (unsigned int c = 0; c < components.size(); ++c)
        block_of_root[components[c]] = std::min(c, max_blocks - 1);
      n_blocks = std::min<std::size_t>(components.size(), max_blocks);

      std::vector<int> block_of(n, -1);
      for (long long i = 0; i < n; ++i)
        if (coupled[i])
          block_of[i] = block_of_root[root(i)];
      return block_of;
    }
  } // namespace

  // The blocks and the layout of the rows over the ranks.
  struct DirectSolver::Factorization
  {
    std::vector<std::unique_ptr<Block>> blocks;
    /** Rows that couple to no other row: their global index and diagonal. */
    std::vector<long long> diagonal_rows;
    std::vector<double>    diagonal_values;
    /** How many blocks were kept from the previous factorisation. */
    unsigned int n_kept = 0;

    MPI_Comm     communicator = MPI_COMM_SELF;
    unsigned int n_ranks = 1, rank = 0;
    Index        n = 0;
    /** Global row of every rank's local rows, rank after rank. */
    std::vector<long long> all_rows;
    /** Rows per rank and their offsets in all_rows. */
    std::vector<int> row_counts, row_offsets;
    /** BLAS threads for the factorisation and many right-hand sides. */
    unsigned int blas_threads = 0;
    /** All right-hand sides, n x m, column by column. */
    std::vector<double> B_full;
    /** This rank's solutions, n x (its columns), column by column. */
    std::vector<double> X_mine;

    /** The upper triangles of all ranks' rows, on every rank. */
    struct Entries
    {
      /** Per row of all_rows: its columns j >= i and their values. */
      std::vector<long long> columns;
      std::vector<double>    values;
      /** Per row of all_rows: how many entries it has. */
      std::vector<int> counts;
    };

    /** Gather the upper triangle of @p K and the row layout. */
    Entries
    gather(const Epetra_CrsMatrix &K);

    /**
     * Split the rows into the blocks that no entry couples (their lower
     * triangles in CHOLMOD's compressed columns, rows sorted) and the rows
     * with only a diagonal entry.
     */
    void
    split(const Entries &entries);

    /** All right-hand sides of @p B into B_full, on every rank. */
    void
    gather_right_hand_sides(const Epetra_MultiVector &B);

    /** Solve the columns [first, last) of B_full into X_mine. */
    void
    solve_columns(const Index first, const Index last);
  };

  DirectSolver::DirectSolver()                         = default;
  DirectSolver::~DirectSolver()                        = default;
  DirectSolver::DirectSolver(DirectSolver &&) noexcept = default;
  DirectSolver &
  DirectSolver::operator=(DirectSolver &&) noexcept = default;

  // Every rank sends the upper triangle of its rows (row i, columns
  // j >= i); read as columns, that is the lower triangle that CHOLMOD
  // stores for a symmetric matrix (stype = -1): column i holds the rows
  // j >= i. All ranks gather all of it, split it into the blocks that no
  // entry couples (the bodies) and factorise each block, or keep its
  // factor from the last call if the block is the same.
  void
  DirectSolver::factorize(const dealii::TrilinosWrappers::SparseMatrix &A)
  {
    matrix                                  = nullptr;
    std::unique_ptr<Factorization> previous = std::move(factorization);
    auto                           f        = std::make_unique<Factorization>();
    f->blas_threads                         = blas_threads();
    ScopedBlasThreads threads(f->blas_threads);
    f->split(f->gather(A.trilinos_matrix()));
    for (auto &block : f->blocks)
      {
        if (previous != nullptr)
          for (auto &old : previous->blocks)
            if (old != nullptr && old->same_matrix(*block))
              {
                block = std::move(old);
                ++f->n_kept;
                break;
              }
        if (block->L == nullptr)
          block->factorise();
      }
    previous.reset();
    matrix        = &A;
    factorization = std::move(f);
  }

  DirectSolver::Factorization::Entries
  DirectSolver::Factorization::gather(const Epetra_CrsMatrix &K)
  {
    const Epetra_BlockMap &rows    = K.RowMap();
    const Epetra_BlockMap &columns = K.ColMap();
    communicator                   = communicator_of(rows);
    int n_all, my_rank;
    MPI_Comm_size(communicator, &n_all);
    MPI_Comm_rank(communicator, &my_rank);
    n_ranks = n_all;
    rank    = my_rank;
    n       = K.NumGlobalRows64();

    std::vector<long long> my_rows(K.NumMyRows()), my_columns;
    std::vector<int>       my_counts(K.NumMyRows());
    std::vector<double>    my_values;
    for (int i = 0; i < K.NumMyRows(); ++i)
      {
        my_rows[i] = rows.GID64(i);
        int     length;
        double *values;
        int    *indices;
        K.ExtractMyRowView(i, length, values, indices);
        for (int k = 0; k < length; ++k)
          {
            const long long j = columns.GID64(indices[k]);
            if (j == my_rows[i] || (j > my_rows[i] && values[k] != 0.))
              {
                my_columns.push_back(j);
                my_values.push_back(values[k]);
                ++my_counts[i];
              }
          }
      }
    Entries entries;
    all_rows        = all_gather_values(my_rows, communicator);
    entries.counts  = all_gather_values(my_counts, communicator);
    entries.columns = all_gather_values(my_columns, communicator);
    entries.values  = all_gather_values(my_values, communicator);
    row_counts.resize(n_ranks);
    const int n_local = my_rows.size();
    MPI_Allgather(&n_local,
                  1,
                  MPI_INT,
                  row_counts.data(),
                  1,
                  MPI_INT,
                  communicator);
    row_offsets = offsets_of(row_counts);
    AssertThrow(static_cast<Index>(all_rows.size()) == n,
                dealii::ExcMessage("The matrix rows are not a partition."));
    return entries;
  }

  // The blocks are the connected components of the matrix's graph
  // (blocks_of_rows()); a row with only its diagonal entry (a constrained
  // DoF) is solved by division. More than eight blocks (a mesh of many
  // bodies) would cost more in bookkeeping than they save: the smaller ones
  // are factorised together.
  void
  DirectSolver::Factorization::split(const Entries &entries)
  {
    std::vector<std::size_t> first_entry(n, 0);
    std::vector<int>         n_entries(n, -1);
    for (std::size_t r = 0, entry = 0; r < all_rows.size(); ++r)
      {
        const long long i = all_rows[r];
        AssertThrow(i >= 0 && i < n && n_entries[i] < 0,
                    dealii::ExcMessage("The matrix rows are not a partition."));
        first_entry[i] = entry;
        n_entries[i]   = entries.counts[r];
        entry += entries.counts[r];
      }

    unsigned int           n_blocks = 0;
    const std::vector<int> block_of =
      blocks_of_rows(n_entries, first_entry, entries.columns, n_blocks);
    blocks.clear();
    for (unsigned int b = 0; b < n_blocks; ++b)
      blocks.push_back(std::make_unique<Block>());

    std::vector<Index> local(n, -1);
    diagonal_rows.clear();
    diagonal_values.clear();
    for (Index i = 0; i < n; ++i)
      if (block_of[i] >= 0)
        {
          Block &block = *blocks[block_of[i]];
          local[i]     = block.rows.size();
          block.rows.push_back(i);
        }
      else
        {
          AssertThrow(n_entries[i] == 1,
                      dealii::ExcMessage("A matrix row has no diagonal."));
          diagonal_rows.push_back(i);
          diagonal_values.push_back(entries.values[first_entry[i]]);
          AssertThrow(diagonal_values.back() > 0,
                      ExcInputError(
                        "The stiffness matrix is not positive definite "
                        "(row " +
                        std::to_string(i) + " has the diagonal entry " +
                        format_number(diagonal_values.back()) +
                        " and no other): a body can move as a rigid body. "
                        "Check the Dirichlet surfaces and the springs."));
        }

    // Each block's lower triangle: its column i holds the rows j >= i of
    // row i's upper triangle (local indices keep the global order).
    std::vector<std::pair<Index, double>> column;
    for (auto &block : blocks)
      {
        block->column_start.assign(1, 0);
        block->row_index.clear();
        block->values.clear();
        for (const long long i : block->rows)
          {
            column.clear();
            for (int k = 0; k < n_entries[i]; ++k)
              column.emplace_back(local[entries.columns[first_entry[i] + k]],
                                  entries.values[first_entry[i] + k]);
            std::sort(column.begin(), column.end());
            for (const auto &[j, a] : column)
              {
                block->row_index.push_back(j);
                block->values.push_back(a);
              }
            block->column_start.push_back(block->row_index.size());
          }
      }
  }

  // All ranks get all right-hand sides; rank r solves the columns
  // [m r / P, m (r + 1) / P) (a contiguous block of the column-major
  // buffer), and one all-gather of the solved blocks gives every rank every
  // solution, of which it keeps its own rows. On one rank no MPI at all.
  void
  DirectSolver::solve(Epetra_MultiVector &X, const Epetra_MultiVector &B)
  {
    Assert(is_factorized(), dealii::ExcMessage("Call factorize() first."));
    Factorization &f = *factorization;
    AssertThrow(B.NumVectors() == X.NumVectors() && B.Map().SameAs(row_map()) &&
                  X.Map().SameAs(row_map()),
                dealii::ExcMessage("X and B must have the matrix's row map "
                                   "and the same number of columns."));
    const Index m = B.NumVectors(), n = f.n;
    f.gather_right_hand_sides(B);
    const long long *my_rows = f.all_rows.data() + f.row_offsets[f.rank];
    const int        n_local = f.row_counts[f.rank];
    const Index      first   = m * f.rank / f.n_ranks,
                last         = m * (f.rank + 1) / f.n_ranks;
    f.solve_columns(first, last);

    if (f.n_ranks == 1)
      {
        for (Index c = 0; c < m; ++c)
          for (int i = 0; i < n_local; ++i)
            X[c][i] = f.X_mine[c * n + my_rows[i]];
        return;
      }
    const std::vector<double> all = all_gather_values(f.X_mine, f.communicator);
    for (Index c = 0; c < m; ++c)
      for (int i = 0; i < n_local; ++i)
        X[c][i] = all[c * n + my_rows[i]];
  }

  void
  DirectSolver::Factorization::gather_right_hand_sides(
    const Epetra_MultiVector &B)
  {
    const Index m = B.NumVectors();
    B_full.resize(n * m);
    const long long *my_rows = all_rows.data() + row_offsets[rank];
    const int        n_local = row_counts[rank];
    if (n_ranks == 1)
      {
        for (Index c = 0; c < m; ++c)
          for (int i = 0; i < n_local; ++i)
            B_full[c * n + my_rows[i]] = B[c][i];
        return;
      }
    // Rank by rank, column by column, the local rows.
    std::vector<double> mine(n_local * m);
    for (Index c = 0; c < m; ++c)
      std::copy(B[c], B[c] + n_local, mine.begin() + c * n_local);
    const std::vector<double> all = all_gather_values(mine, communicator);
    for (unsigned int r = 0, start = 0; r < n_ranks; ++r)
      {
        const long long *rows = all_rows.data() + row_offsets[r];
        for (Index c = 0; c < m; ++c)
          for (int i = 0; i < row_counts[r]; ++i)
            B_full[c * n + rows[i]] = all[start + c * row_counts[r] + i];
        start += row_counts[r] * m;
      }
  }

  // Each block solves the columns whose right-hand side is not zero on its
  // rows (a unit load on one body: that body's block only), the diagonal
  // rows are divided.
  void
  DirectSolver::Factorization::solve_columns(const Index first,
                                             const Index last)
  {
    const Index n_mine = std::max<Index>(last - first, 0);
    X_mine.assign(n * n_mine, 0.);
    if (n_mine == 0)
      return;
    const double *B_mine = B_full.data() + first * n;
    for (Index c = 0; c < n_mine; ++c)
      for (unsigned int d = 0; d < diagonal_rows.size(); ++d)
        X_mine[c * n + diagonal_rows[d]] =
          B_mine[c * n + diagonal_rows[d]] / diagonal_values[d];
    std::vector<double> B_block;
    std::vector<Index>  columns;
    for (const auto &block : blocks)
      {
        const Index n_block = block->n_rows();
        columns.clear();
        for (Index c = 0; c < n_mine; ++c)
          for (const long long i : block->rows)
            if (B_mine[c * n + i] != 0.)
              {
                columns.push_back(c);
                break;
              }
        if (columns.empty())
          continue;
        B_block.resize(n_block * columns.size());
        for (std::size_t k = 0; k < columns.size(); ++k)
          for (Index r = 0; r < n_block; ++r)
            B_block[k * n_block + r] = B_mine[columns[k] * n + block->rows[r]];
        const double *x =
          block->solve(B_block.data(), columns.size(), blas_threads);
        for (std::size_t k = 0; k < columns.size(); ++k)
          for (Index r = 0; r < n_block; ++r)
            X_mine[columns[k] * n + block->rows[r]] = x[k * n_block + r];
      }
  }

  const Epetra_Map &
  DirectSolver::row_map() const
  {
    Assert(matrix != nullptr, dealii::ExcMessage("Call factorize() first."));
    return matrix->trilinos_matrix().RowMap();
  }

  bool
  DirectSolver::is_factorized() const
  {
    return factorization != nullptr;
  }

  unsigned int
  DirectSolver::n_blocks() const
  {
    Assert(is_factorized(), dealii::ExcMessage("Call factorize() first."));
    return factorization->blocks.size();
  }

  unsigned int
  DirectSolver::n_kept_blocks() const
  {
    Assert(is_factorized(), dealii::ExcMessage("Call factorize() first."));
    return factorization->n_kept;
  }

  double
  DirectSolver::n_factor_nonzeros() const
  {
    Assert(is_factorized(), dealii::ExcMessage("Call factorize() first."));
    double n_nonzeros = factorization->diagonal_rows.size();
    for (const auto &block : factorization->blocks)
      n_nonzeros += block->common.lnz;
    return n_nonzeros;
  }

  double
  DirectSolver::reciprocal_condition_estimate() const
  {
    Assert(is_factorized(), dealii::ExcMessage("Call factorize() first."));
    double rcond = 1;
    for (const auto &block : factorization->blocks)
      rcond = std::min(rcond, cholmod_l_rcond(block->L, &block->common));
    return rcond;
  }

  unsigned int
  DirectSolver::blas_threads()
  {
    const OpenBlasThreads blas;
    if (blas.set == nullptr || blas.get == nullptr)
      return 0;
    for (const char *variable :
         {"OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS"})
      if (std::getenv(variable) != nullptr)
        return 0;

    unsigned int n_cores = std::max(1u, std::thread::hardware_concurrency());
    cpu_set_t    affinity;
    if (sched_getaffinity(0, sizeof(affinity), &affinity) == 0)
      n_cores = std::max(1, CPU_COUNT(&affinity));
    return std::max(1u, n_cores / ranks_on_this_node());
  }

  std::string
  DirectSolver::blas_library()
  {
    Dl_info info;
    void   *dgemm = dlsym(RTLD_DEFAULT, "dgemm_");
    if (dgemm == nullptr || dladdr(dgemm, &info) == 0 ||
        info.dli_fname == nullptr)
      return "(unknown)";
    char *path = realpath(info.dli_fname, nullptr);
    if (path == nullptr)
      return info.dli_fname;
    const std::string result = path;
    std::free(path);
    return result;
  }
} // namespace TKR::Elasticity
