/* The plain C interface between needlesim and an MPM step back-end (the CUDA
 * plugin libneedlesim_mpm_cuda.so, or the host emulation of its kernels):
 * POD structs and one table of functions, so the plugin is built by nvcc alone
 * and loaded with dlopen. All quantities SI, fp64. Particle arrays are
 * structures of arrays: component c of point p at [c * n + p]. Grid node
 * (i, j, k) is (i * ny + j) * nz + k. */
#ifndef NEEDLESIM_MPM_DEVICE_ABI_H
#define NEEDLESIM_MPM_DEVICE_ABI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NSMPM_ABI_VERSION 1
#define NSMPM_MAX_RIGIDS 4
#define NSMPM_MAX_MATERIALS 16

enum NsMpmLaw { NSMPM_FUNG = 0, NSMPM_NEO_HOOKEAN = 1 };
enum NsMpmRigidKind { NSMPM_PLANE = 0, NSMPM_NEEDLE = 1 };
enum NsMpmTip { NSMPM_CONICAL = 0, NSMPM_BEVEL = 1, NSMPM_BLUNT = 2 };
/* P2G and G2P variants: NAIVE = one thread per point in storage order,
 * global atomics; SORTED = points sorted by cell every step, warp-aggregated
 * adds of neighbours that share nodes (the default). */
enum NsMpmKernel { NSMPM_KERNEL_SORTED = 0, NSMPM_KERNEL_NAIVE = 1 };

typedef struct NsMpmMaterial {
  int law;        /* NsMpmLaw */
  double mu;      /* Fung-Demiray: mu, Pa */
  double gamma;   /* Fung-Demiray: gamma */
  double c10;     /* neo-Hookean: C10, Pa */
  double bulk;    /* K, Pa */
  double rho0;    /* density times the mass scaling, kg/m^3 */
} NsMpmMaterial;

typedef struct NsMpmRigid {
  int kind;       /* NsMpmRigidKind */
  int tip;        /* NsMpmTip */
  double point[3], normal[3], axis[3], bevelSide[3];
  double radius, tipAngle;
  double velocity[3];
  double friction;
} NsMpmRigid;

typedef struct NsMpmConfig {
  int abiVersion;          /* NSMPM_ABI_VERSION */
  double h;                /* grid spacing */
  double origin[3];        /* node (0, 0, 0) */
  int nodes[3];            /* nodes along each axis */
  int support;             /* 2: linear hat, 3: quadratic B-spline */
  int musl;                /* 1: MUSL, 0: USL */
  double flip;
  double gravity[3];
  double contactGap;       /* eq 22 gap of the rigid grid contact */
  int kernel;              /* NsMpmKernel */
  int nMaterials;
  NsMpmMaterial materials[NSMPM_MAX_MATERIALS];
  int nRigids;
} NsMpmConfig;

/* Particle state, host side: n points, arrays of 3 n (x, v), 9 n (F, row
 * major), 6 n (Cauchy stress, Voigt 11 22 33 12 23 13), n (others). */
typedef struct NsMpmParticles {
  size_t n;
  double *x, *v, *F, *sig, *mass, *vol0, *vol;
  uint8_t* material;
} NsMpmParticles;

/* Per node: fixed velocity components (bits 0-2), Lysmer dashpots (3 per node). */
typedef struct NsMpmGrid {
  const uint8_t* fixMask;
  const double* dashpot;
} NsMpmGrid;

typedef struct NsMpmStepIn {
  double dt;
  NsMpmRigid rigids[NSMPM_MAX_RIGIDS];  /* this step's positions and velocities */
} NsMpmStepIn;

typedef struct NsMpmStepOut {
  double kinetic, internal, maxSpeed;
  double force[NSMPM_MAX_RIGIDS][9];    /* per rigid: total (3), shaft (3), tip (3), N */
  int contactNodes[NSMPM_MAX_RIGIDS];
  int failure;                          /* 0 ok; 1 det F <= 0, 2 not finite, 3 left the grid */
  size_t failedPoint;                   /* original index of the point */
} NsMpmStepOut;

typedef struct NsMpmBackend {
  int abiVersion;
  /* Number of usable devices (0: none), a line naming the first or the reason in msg. */
  int (*probe)(char* msg, size_t len);
  /* Uploads the set-up; null with the reason in err on failure. */
  void* (*create)(const NsMpmConfig* cfg, const NsMpmParticles* particles, const NsMpmGrid* grid, char* err,
                  size_t len);
  /* One step; 0 on success, else an error (a CUDA failure) in err. */
  int (*step)(void* run, const NsMpmStepIn* in, NsMpmStepOut* out, char* err, size_t len);
  /* Copies x, v, F, sig and vol back into out (arrays sized as at create), in the original point order. */
  int (*download)(void* run, NsMpmParticles* out, char* err, size_t len);
  void (*destroy)(void* run);
} NsMpmBackend;

/* The plugin's one exported symbol. */
typedef const NsMpmBackend* (*NsMpmBackendEntry)(void);
const NsMpmBackend* needlesim_mpm_backend(void);

#ifdef __cplusplus
}
#endif

#endif
