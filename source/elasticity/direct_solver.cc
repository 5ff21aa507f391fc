// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/elasticity/direct_solver.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_MpiComm.h>
#include <dlfcn.h>
#include <mpi.h>
#include <sched.h>
#include <suitesparse/cholmod.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <memory>
#include <thread>
#include <utility>
#include <vector>

namespace TKR::Elasticity
{
  namespace
  {
    using Index = SuiteSparse_long;

    MPI_Comm
    communicator_of(const Epetra_BlockMap &map)
    {
      const auto *comm = dynamic_cast<const Epetra_MpiComm *>(&map.Comm());
      return comm != nullptr ? comm->Comm() : MPI_COMM_SELF;
    }

    /** OpenBLAS' thread control (null with another BLAS). */
    struct OpenBlasThreads
    {
      using Set = void (*)(int);
      using Get = int (*)();
      Set set =
        reinterpret_cast<Set>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
      Get get =
        reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    };

    /**
     * The BLAS runs with @p n threads while this object lives (nothing
     * happens for n = 0 or with another BLAS than OpenBLAS).
     */
    class ScopedBlasThreads
    {
    public:
      explicit ScopedBlasThreads(const unsigned int n)
      {
        if (n == 0 || blas.set == nullptr || blas.get == nullptr)
          return;
        previous = blas.get();
        if (previous != static_cast<int>(n))
          blas.set(n);
      }

      ~ScopedBlasThreads()
      {
        if (previous > 0 && previous != blas.get())
          blas.set(previous);
      }

    private:
      OpenBlasThreads blas;
      int             previous = 0;
    };

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
  } // namespace

  // CHOLMOD's objects, freed in the destructor: the workspace (common), the
  // factor L and the dense buffers that cholmod_l_solve2() reuses (it
  // reallocates them whenever the number of columns changes, so one set for
  // single right-hand sides and one for batches). Also the layout of the
  // rows over the ranks.
  struct DirectSolver::Factorization
  {
    struct SolveBuffers
    {
      cholmod_dense *X = nullptr, *Y = nullptr, *E = nullptr;
    };

    cholmod_common  common;
    cholmod_factor *L = nullptr;
    SolveBuffers    single, batch;

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

    Factorization()
    {
      cholmod_l_start(&common);
      // The errors become exceptions below; CHOLMOD prints nothing.
      common.print = 0;
      // Supernodal: the dense blocks of L go to the BLAS, where an optimised
      // BLAS makes the difference (doc/performance.md).
      common.supernodal = CHOLMOD_SUPERNODAL;
      // The ordering: CHOLMOD's default strategy, AMD, and METIS as well if
      // AMD's factor is dense (and then the smaller one). On the medium TKR
      // mesh METIS gives 35 % fewer nonzeros in L and a third of the flops
      // (doc/performance.md); on the coarse mesh AMD is as good and cheaper.
      common.nmethods = 0;
    }

    ~Factorization()
    {
      for (SolveBuffers *buffers : {&single, &batch})
        {
          cholmod_l_free_dense(&buffers->X, &common);
          cholmod_l_free_dense(&buffers->Y, &common);
          cholmod_l_free_dense(&buffers->E, &common);
        }
      cholmod_l_free_factor(&L, &common);
      cholmod_l_finish(&common);
    }

    Factorization(const Factorization &) = delete;
    Factorization &
    operator=(const Factorization &) = delete;

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

    /** The lower triangle in CHOLMOD's compressed columns. */
    std::unique_ptr<cholmod_sparse, std::function<void(cholmod_sparse *)>>
    lower_triangle(const Entries &entries);

    /** Order and factorise @p lower; refuse a singular matrix. */
    void
    factorise(cholmod_sparse *lower);

    /** All right-hand sides of @p B into B_full, on every rank. */
    void
    gather_right_hand_sides(const Epetra_MultiVector &B);

    /** Solve the columns [first, last) of B_full; the buffers used. */
    SolveBuffers &
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
  // j >= i. All ranks gather all of it and factorise the whole matrix.
  void
  DirectSolver::factorize(const dealii::TrilinosWrappers::SparseMatrix &A)
  {
    matrix = nullptr;
    factorization.reset();
    auto f          = std::make_unique<Factorization>();
    f->blas_threads = blas_threads();
    ScopedBlasThreads threads(f->blas_threads);
    const auto        entries = f->gather(A.trilinos_matrix());
    const auto        lower   = f->lower_triangle(entries);
    f->factorise(lower.get());
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

  // Compressed columns, the rows of each column sorted.
  std::unique_ptr<cholmod_sparse, std::function<void(cholmod_sparse *)>>
  DirectSolver::Factorization::lower_triangle(const Entries &entries)
  {
    std::unique_ptr<cholmod_sparse, std::function<void(cholmod_sparse *)>>
      lower(cholmod_l_allocate_sparse(n,
                                      n,
                                      entries.values.size(),
                                      /*sorted=*/true,
                                      /*packed=*/true,
                                      /*stype=*/-1,
                                      CHOLMOD_REAL,
                                      &common),
            [this](cholmod_sparse *S) { cholmod_l_free_sparse(&S, &common); });
    AssertThrow(lower != nullptr,
                ExcInputError("CHOLMOD could not allocate the matrix (out of "
                              "memory?)."));
    auto                    *column_start = static_cast<Index *>(lower->p);
    auto                    *row_index    = static_cast<Index *>(lower->i);
    auto                    *value        = static_cast<double *>(lower->x);
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
    column_start[0] = 0;
    std::vector<std::pair<long long, double>> column;
    for (Index i = 0; i < n; ++i)
      {
        column.clear();
        for (int k = 0; k < n_entries[i]; ++k)
          column.emplace_back(entries.columns[first_entry[i] + k],
                              entries.values[first_entry[i] + k]);
        std::sort(column.begin(), column.end());
        Index p = column_start[i];
        for (const auto &[j, a] : column)
          {
            row_index[p] = j;
            value[p]     = a;
            ++p;
          }
        column_start[i + 1] = p;
      }
    return lower;
  }

  void
  DirectSolver::Factorization::factorise(cholmod_sparse *lower)
  {
    L = cholmod_l_analyze(lower, &common);
    AssertThrow(L != nullptr,
                ExcInputError("CHOLMOD could not order the stiffness matrix "
                              "(status " +
                              std::to_string(common.status) + ")."));
    cholmod_l_factorize(lower, L, &common);
    AssertThrow(
      common.status != CHOLMOD_NOT_POSDEF && static_cast<Index>(L->minor) == n,
      ExcInputError("The stiffness matrix is singular or not positive definite "
                    "(CHOLMOD: pivot " +
                    std::to_string(L->minor) + " of " + std::to_string(n) +
                    "): a body can move as a rigid body. Check the Dirichlet "
                    "surfaces and the springs."));
    AssertThrow(common.status >= CHOLMOD_OK,
                ExcInputError("CHOLMOD could not factorise the stiffness "
                              "matrix (status " +
                              std::to_string(common.status) +
                              "; out of memory?)."));
    // A rigid-body mode in floating point need not give a negative pivot,
    // only one at round-off level: (min L_ii / max L_ii)^2 about 1e-16.
    // The gait stiffness matrices of the TKR meshes have 1e-6 (coarse
    // 1.2e-6, medium 3.4e-6).
    const double rcond = cholmod_l_rcond(L, &common);
    AssertThrow(rcond > 1e-14,
                ExcInputError(
                  "The stiffness matrix is singular (CHOLMOD's reciprocal "
                  "condition estimate is " +
                  format_number(rcond) +
                  "): a body can move as a rigid body. Check the Dirichlet "
                  "surfaces and the springs."));
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
    const Factorization::SolveBuffers &buffers = f.solve_columns(first, last);

    if (f.n_ranks == 1)
      {
        const double *x = static_cast<const double *>(buffers.X->x);
        for (Index c = 0; c < m; ++c)
          for (int i = 0; i < n_local; ++i)
            X[c][i] = x[c * n + my_rows[i]];
        return;
      }
    std::vector<double> solved(
      last > first ? static_cast<const double *>(buffers.X->x) : nullptr,
      last > first ?
        static_cast<const double *>(buffers.X->x) + n * (last - first) :
        nullptr);
    const std::vector<double> all = all_gather_values(solved, f.communicator);
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

  DirectSolver::Factorization::SolveBuffers &
  DirectSolver::Factorization::solve_columns(const Index first,
                                             const Index last)
  {
    SolveBuffers &buffers = (last - first == 1) ? single : batch;
    if (last <= first)
      return buffers;
    // BLAS threads only for many columns: with a few, the supernodal
    // solve is a sequence of matrix-vector products, bound by memory
    // bandwidth, and threads only cost synchronisation (one right-hand
    // side on the medium TKR mesh: 30-37 ms with one thread, 37-92 ms
    // with two; doc/performance.md).
    ScopedBlasThreads threads(last - first >= 8 ? blas_threads :
                              blas_threads > 0  ? 1 :
                                                  0);
    // A header for this rank's columns of B_full (CHOLMOD only reads B).
    cholmod_dense B_mine;
    B_mine.nrow  = n;
    B_mine.ncol  = last - first;
    B_mine.nzmax = n * (last - first);
    B_mine.d     = n;
    B_mine.x     = B_full.data() + first * n;
    B_mine.z     = nullptr;
    B_mine.xtype = CHOLMOD_REAL;
    B_mine.dtype = CHOLMOD_DOUBLE;
    const int ok = cholmod_l_solve2(CHOLMOD_A,
                                    L,
                                    &B_mine,
                                    nullptr,
                                    &buffers.X,
                                    nullptr,
                                    &buffers.Y,
                                    &buffers.E,
                                    &common);
    AssertThrow(ok != 0,
                dealii::ExcMessage("CHOLMOD solve failed (status " +
                                   std::to_string(common.status) + ")."));
    return buffers;
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

  double
  DirectSolver::n_factor_nonzeros() const
  {
    Assert(is_factorized(), dealii::ExcMessage("Call factorize() first."));
    return factorization->common.lnz;
  }

  double
  DirectSolver::reciprocal_condition_estimate() const
  {
    Assert(is_factorized(), dealii::ExcMessage("Call factorize() first."));
    return cholmod_l_rcond(factorization->L, &factorization->common);
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
