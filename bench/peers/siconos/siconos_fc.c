/* siconos_fc: solve one frictional-contact problem with Siconos numerics, or judge a given
 * solution, with one independent error routine.
 *
 *   siconos_fc FILE --info                      -> "INFO d nc storage"
 *   siconos_fc FILE --solver NAME --tol T [--max-iter N] [--repeat K]
 *                              -> "RESULT solver tol info iter seconds self indep warm repeats"
 *   siconos_fc FILE --reactions R               -> "REACTIONS indep"
 *
 * FILE is read with Siconos' own reader (frictionContact_new_from_filename). NAME is one of the
 * short names in the table below; "NSGS" means the 2D or the 3D NSGS according to the file.
 * One problem per process: run.sh repeats runs and wraps each in `timeout`, so a solver that
 * hangs or crashes costs one line of the table, not the whole benchmark. With --repeat K the
 * problem is solved up to K times in the process, each time from r = 0 on a freshly read copy
 * with fresh options (reading untimed), further solves only while the solves so far took
 * under 0.1 s in all (the rule of Sable's `fc3d --repeat`): `seconds` is the first solve's
 * time, `warm` the median of the others (0 when there were none), and iterations, errors and
 * the judged reactions are the first solve's.
 *
 * The independent error (indep_error) is the one routine that judges every answer, Siconos'
 * and Sable's alike:  u = W r + q,
 *   e = ||r - P_K(r - (u + mu*|u_T|*e_N))|| / max(||q||, ||r||, ||u||),
 * with P_K the projection on the product of Coulomb cones, blocks [N, T] or [N, T1, T2]. It
 * uses only W (through NM_gemv), q and mu from a second, untouched copy of the problem, so
 * nothing a solver does to its own copy (rescaling, format conversion) can leak into it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <siconos/numerics/FrictionContactProblem.h>
#include <siconos/numerics/Friction_cst.h>
#include <siconos/numerics/NonSmoothDrivers.h>
#include <siconos/numerics/NumericsMatrix.h>
#include <siconos/numerics/SolverOptions.h>
#include <siconos/numerics/SparseBlockMatrix.h>

/* Short name -> Siconos solver id, for d = 3 and d = 2, with the iteration cap we give it:
 * generous for first-order methods (many cheap sweeps), smaller for Newton-type methods. */
typedef struct {
  const char* name;
  int dim;
  int id;
  int max_iter; /* 0: keep Siconos' default (pivoting methods count pivots, not sweeps) */
} SolverEntry;

static const SolverEntry kSolvers[] = {
    {"NSGS", 3, SICONOS_FRICTION_3D_NSGS, 100000},
    {"NSN_AC", 3, SICONOS_FRICTION_3D_NSN_AC, 1000},
    {"NSN_AC_TEST", 3, SICONOS_FRICTION_3D_NSN_AC_TEST, 1000},
    {"NSN_FB", 3, SICONOS_FRICTION_3D_NSN_FB, 1000},
    {"NSN_NM", 3, SICONOS_FRICTION_3D_NSN_NM, 1000},
    {"PROX", 3, SICONOS_FRICTION_3D_PROX, 1000},
    {"ADMM", 3, SICONOS_FRICTION_3D_ADMM, 100000},
    {"NSGS", 2, SICONOS_FRICTION_2D_NSGS, 100000},
    {"CPG", 2, SICONOS_FRICTION_2D_CPG, 100000},
    {"LEMKE", 2, SICONOS_FRICTION_2D_LEMKE, 0},
    {"ENUM", 2, SICONOS_FRICTION_2D_ENUM, 0},
};

static const SolverEntry* find_solver(const char* name, int dim) {
  for (size_t i = 0; i < sizeof kSolvers / sizeof kSolvers[0]; ++i)
    if (kSolvers[i].dim == dim && strcmp(kSolvers[i].name, name) == 0) return &kSolvers[i];
  return NULL;
}

static double norm2(const double* x, int n) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += x[i] * x[i];
  return sqrt(s);
}

/* Projection of v (d components, [N, T...]) on the cone {x : |x_T| <= mu x_N}, in place. */
static void project_on_cone(double* v, int d, double mu) {
  double vt = 0.0;
  for (int k = 1; k < d; ++k) vt += v[k] * v[k];
  vt = sqrt(vt);
  if (v[0] >= 0.0 && vt <= mu * v[0]) return; /* inside the cone (v[0] >= 0: for mu = 0) */
  if (mu * vt <= -v[0]) {                     /* inside the polar cone: projects to the apex */
    for (int k = 0; k < d; ++k) v[k] = 0.0;
    return;
  }
  const double pn = (v[0] + mu * vt) / (1.0 + mu * mu); /* onto the cone's surface */
  v[0] = pn;
  for (int k = 1; k < d; ++k) v[k] = mu * pn * v[k] / vt; /* vt > 0 here */
}

/* The independent error of reaction r for the problem p (see the header comment). */
static double indep_error(FrictionContactProblem* p, const double* r) {
  const int d = p->dimension, nc = p->numberOfContacts, n = d * nc;
  double* u = malloc(sizeof(double) * (size_t)n);
  memcpy(u, p->q, sizeof(double) * (size_t)n);
  NM_gemv(1.0, p->M, r, 1.0, u); /* u = W r + q */
  double sum = 0.0, v[3];
  for (int c = 0; c < nc; ++c) {
    const double* rc = r + d * c;
    const double* uc = u + d * c;
    double ut = 0.0;
    for (int k = 1; k < d; ++k) ut += uc[k] * uc[k];
    ut = sqrt(ut);
    /* v = r - (u + mu |u_T| e_N), then r - P_K(v) */
    for (int k = 0; k < d; ++k) v[k] = rc[k] - uc[k];
    v[0] -= p->mu[c] * ut;
    project_on_cone(v, d, p->mu[c]);
    for (int k = 0; k < d; ++k) sum += (rc[k] - v[k]) * (rc[k] - v[k]);
  }
  double scale = fmax(norm2(p->q, n), fmax(norm2(r, n), norm2(u, n)));
  if (scale == 0.0) scale = 1.0; /* all-zero problem: report the absolute residual */
  free(u);
  return sqrt(sum) / scale;
}

static FrictionContactProblem* load(const char* file) {
  FrictionContactProblem* p = frictionContact_new_from_filename(file);
  if (!p) {
    fprintf(stderr, "siconos_fc: cannot read %s\n", file);
    exit(2);
  }
  return p;
}

static int read_reactions(const char* file, double* r, int n) {
  FILE* f = fopen(file, "r");
  if (!f) return -1;
  int i = 0;
  while (i < n && fscanf(f, "%lf", &r[i]) == 1) ++i;
  double extra;
  const int more = fscanf(f, "%lf", &extra) == 1; /* a longer file is not this problem's */
  fclose(f);
  return (i == n && !more) ? 0 : -1;
}

static int usage(void) {
  fprintf(stderr,
          "usage: siconos_fc FILE --info\n"
          "       siconos_fc FILE --solver NAME --tol T [--max-iter N] [--repeat K]\n"
          "       siconos_fc FILE --reactions R\n");
  return 2;
}

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const char* file = argv[1];
  const char *solver = NULL, *reactions = NULL;
  double tol = 1e-4;
  int max_iter = -1, info_only = 0, repeat = 1;
  for (int i = 2; i < argc; ++i) {
    if (!strcmp(argv[i], "--info"))
      info_only = 1;
    else if (!strcmp(argv[i], "--solver") && i + 1 < argc)
      solver = argv[++i];
    else if (!strcmp(argv[i], "--tol") && i + 1 < argc)
      tol = atof(argv[++i]);
    else if (!strcmp(argv[i], "--max-iter") && i + 1 < argc)
      max_iter = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--repeat") && i + 1 < argc)
      repeat = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--reactions") && i + 1 < argc)
      reactions = argv[++i];
    else
      return usage();
  }

  /* The judge's copy: read separately and never handed to a solver. */
  FrictionContactProblem* judge = load(file);
  const int d = judge->dimension, nc = judge->numberOfContacts, n = d * nc;

  if (info_only) {
    printf("INFO %d %d %d\n", d, nc, (int)judge->M->storageType);
    return 0;
  }

  if (reactions) {
    double* r = calloc((size_t)n, sizeof(double));
    if (read_reactions(reactions, r, n) != 0) {
      fprintf(stderr, "siconos_fc: %s does not hold %d values\n", reactions, n);
      return 2;
    }
    printf("REACTIONS %.3e\n", indep_error(judge, r));
    return 0;
  }

  if (!solver) return usage();
  const SolverEntry* entry = find_solver(solver, d);
  if (!entry) {
    fprintf(stderr, "siconos_fc: no solver %s for d = %d\n", solver, d);
    return 2;
  }

  if (max_iter < 0) max_iter = entry->max_iter;
  if (repeat < 1) return usage();
  double* r = NULL;
  int info = 0, iters = 0;
  double first = 0.0, self = 0.0, spent = 0.0, warm[1000];
  int nwarm = 0;
  for (int k = 0; k < repeat && k < 1001 && (k == 0 || spent < 0.1); ++k) {
    FrictionContactProblem* p = load(file);
    /* Siconos 4.4's fc2d_driver aborts on NM_SPARSE (CSC) storage; its NSGS is written for
     * dense or sparse-block matrices. So a 2D problem stored as NM_SPARSE is converted to
     * sparse-block with d x d blocks, outside the timed region, like reading the file. */
    if (d == 2 && p->M->storageType == NM_SPARSE) {
      SparseBlockStructuredMatrix* sbm = SBM_new();
      if (SBM_from_csparse(d, NM_csc(p->M), sbm) != 0) {
        fprintf(stderr, "siconos_fc: cannot convert %s to sparse-block\n", file);
        return 2;
      }
      NumericsMatrix* blocks = NM_new();
      NM_fill(blocks, NM_SPARSE_BLOCK, n, n, sbm);
      p->M = blocks;
    }
    SolverOptions* options = solver_options_create(entry->id); /* Siconos' defaults */
    options->dparam[SICONOS_DPARAM_TOL] = tol;
    if (max_iter > 0) options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iter;

    double* rk = calloc((size_t)n, sizeof(double)); /* start from r = 0, as Sable does */
    double* u = calloc((size_t)n, sizeof(double));
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    const int info_k = d == 2 ? fc2d_driver(p, rk, u, options) : fc3d_driver(p, rk, u, options);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    const double seconds =
        (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    spent += seconds;
    if (k == 0) { /* the first solve is the one reported and judged */
      r = rk;
      info = info_k;
      iters = options->iparam[SICONOS_IPARAM_ITER_DONE];
      self = options->dparam[SICONOS_DPARAM_RESIDU];
      first = seconds;
    } else {
      warm[nwarm++] = seconds;
    }
  }
  /* the median of the warm solves (insertion sort: at most 1000) */
  for (int i = 1; i < nwarm; ++i)
    for (int j = i; j > 0 && warm[j - 1] > warm[j]; --j) {
      const double t = warm[j];
      warm[j] = warm[j - 1];
      warm[j - 1] = t;
    }
  const double warm_median =
      nwarm == 0 ? 0.0
                 : (nwarm % 2 ? warm[nwarm / 2] : 0.5 * (warm[nwarm / 2 - 1] + warm[nwarm / 2]));

  /* info == 0 is the solver's own "converged"; iterations and error are its own counters. */
  printf("RESULT %s %.0e %d %d %.6f %.3e %.3e %.9f %d\n", entry->name, tol, info, iters, first,
         self, indep_error(judge, r), warm_median, 1 + nwarm);
  return 0; /* no frees: the process ends here */
}
