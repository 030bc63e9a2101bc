/* The comparison's kernels (designer.evaluate._ckernels). Arrays are C-contiguous,
 * double or int64_t, row-major; outputs are allocated by the caller (Python) unless
 * said otherwise. Coordinates are local (world - an origin), metres. */
#ifndef DESIGNER_KERNELS_H
#define DESIGNER_KERNELS_H

#include <stdint.h>

/* bvh.c: bounding-volume hierarchy over triangles, exact nearest-triangle queries */
void centroid_codes(const double *local, const int64_t *faces, int64_t m, const double lo[3],
                    const double scale[3], uint64_t *out, int n_threads);
/* stable argsort; returns 0, or -1 when out of memory */
int radix_argsort(const uint64_t *codes, int64_t n, int64_t *order);
/* box (2m - 1, 6), link (2m - 1, 2): returns the number of nodes, -1 on a too deep tree */
int64_t build_bvh(const uint64_t *codes, const double *tri, int64_t m, double *box,
                  int64_t *link);

typedef struct {
    const double *tri;           /* (M, 9) in BVH order */
    const double *box;           /* (K, 6) */
    const int64_t *link;         /* (K, 2) */
    const double *normals_face;  /* (M, 3) */
    const int64_t *neighbours;   /* (M, 3) */
    const double *crowded;       /* (E, 3) */
    const double *normals_vert;  /* (V, 3) */
    const int64_t *corner_vertex;/* (M, 3) */
} mesh_index_t;

/* signed distance (and nearest triangle, when `nearest` is not NULL) of each world point
 * (n, 3): local = world - origin; lo and scale define the Morton grid that orders the
 * points; points farther than sqrt(limit_d2) get NaN and -1. Returns 0, -1 on memory. */
int query(const double *points_world, int64_t n, const double origin[3], const double lo[3],
          const double scale[3], const mesh_index_t *mesh, double limit_d2, double *dist,
          int64_t *nearest, int n_threads);

/* topology.c: welding, face geometry and pseudo-normals */
void weld_vertices(const double *vertices, int64_t n, const int64_t *candidates, int64_t m,
                   int64_t *out);
void face_geometry(const double *local, const int64_t *faces, int64_t m, double *tri,
                   double *normal, double *angle, int n_threads);
void vertex_normals(const int64_t *faces, int64_t m, const double *normal, const double *angle,
                    double *vert);
/* neighbour (M, 3); *sums (E, 3) is malloc'ed (free() it), *n_crowded = E; returns 0, or
 * -1 when out of memory */
int edge_neighbours(const int64_t *faces, int64_t m, int64_t n_vertices, const double *normal,
                    int64_t *neighbour, double **sums, int64_t *n_crowded, int n_threads);

/* grid.c: nearest point to each cell centre of a north-up grid (returns 0, -1 on memory) */
int nearest_point_grid(const double *x, const double *y, int64_t n, int64_t rows,
                       int64_t cols, double cell, double gap, int64_t *out, int n_threads);

/* grid.c: highest triangle over each cell centre (rasters) */
void highest_surface(const double *xy_local, const double *z, const int64_t *faces, int64_t m,
                     double cell, int64_t rows, int64_t cols, double *out);

#endif
