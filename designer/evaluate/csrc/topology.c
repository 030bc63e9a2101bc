/* Mesh topology for the sign: welding, face geometry and pseudo-normals.
 *
 * The sign of a distance comes from the pseudo-normal of the nearest feature (Baerentzen
 * & Aanaes 2005): the face normal; for an edge, the sum of the normals of the faces
 * sharing it (one face on a boundary); for a vertex, the angle-weighted sum of its
 * faces' normals. Edges are found by a counting sort of their smaller vertex id, so no
 * hashing of every edge is needed; only vertices on open edges are hashed, to weld
 * corners that were split with bit-identical coordinates. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernels.h"
#include "parallel.h"

/* splitmix64's finaliser: every input bit reaches the low bits the table index uses
 * (coordinates on a grid have mantissas ending in many zero bits) */
static inline uint64_t mix(uint64_t h)
{
    h ^= h >> 30;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27;
    h *= 0x94D049BB133111EBull;
    h ^= h >> 31;
    return h;
}

void weld_vertices(const double *vertices, int64_t n, const int64_t *candidates, int64_t m,
                   int64_t *out)
{
    /* canonical index of each vertex: among candidates, the first with bit-identical
     * x, y, z; every other vertex maps to itself */
    const uint64_t *bits = (const uint64_t *)vertices;
    for (int64_t i = 0; i < n; i++)
        out[i] = i;
    int64_t size = 1;
    while (size < 2 * m)
        size <<= 1;
    int64_t *table = malloc(sizeof(int64_t) * size);
    if (table == NULL)
        return; /* nothing welded: the signs of open seams stay as they are */
    memset(table, 0xff, sizeof(int64_t) * size);  /* -1 */
    uint64_t mask = (uint64_t)(size - 1);
    for (int64_t c = 0; c < m; c++) {
        int64_t i = candidates[c];
        const uint64_t *p = bits + 3 * i;
        uint64_t slot = mix(mix(mix(p[0]) ^ p[1]) ^ p[2]) & mask;
        for (;;) {
            int64_t j = table[slot];
            if (j < 0) {
                table[slot] = i;
                break;
            }
            const uint64_t *q = bits + 3 * j;
            if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
                out[i] = j;
                break;
            }
            slot = (slot + 1) & mask;
        }
    }
    free(table);
}

typedef struct {
    const double *local;
    const int64_t *faces;
    double *tri, *normal, *angle;
} geometry_ctx;

static void geometry_range(void *arg, int64_t b, int64_t e)
{
    geometry_ctx *g = arg;
    for (int64_t f = b; f < e; f++) {
        double *t = g->tri + 9 * f;
        for (int c = 0; c < 3; c++)
            for (int a = 0; a < 3; a++)
                t[3 * c + a] = g->local[3 * g->faces[3 * f + c] + a];
        double e1x = t[3] - t[0], e1y = t[4] - t[1], e1z = t[5] - t[2];
        double e2x = t[6] - t[0], e2y = t[7] - t[1], e2z = t[8] - t[2];
        double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
        double length = sqrt(nx * nx + ny * ny + nz * nz);
        double *n = g->normal + 3 * f;
        if (length > 0.0)
            n[0] = nx / length, n[1] = ny / length, n[2] = nz / length;
        else
            n[0] = n[1] = n[2] = 0.0;
        for (int c = 0; c < 3; c++) {
            int i = 3 * c, j = 3 * ((c + 1) % 3), k = 3 * ((c + 2) % 3);
            double ux = t[j] - t[i], uy = t[j + 1] - t[i + 1], uz = t[j + 2] - t[i + 2];
            double vx = t[k] - t[i], vy = t[k + 1] - t[i + 1], vz = t[k + 2] - t[i + 2];
            double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
            g->angle[3 * f + c] = atan2(sqrt(cx * cx + cy * cy + cz * cz),
                                        ux * vx + uy * vy + uz * vz);
        }
    }
}

void face_geometry(const double *local, const int64_t *faces, int64_t m, double *tri,
                   double *normal, double *angle, int n_threads)
{
    geometry_ctx g = {local, faces, tri, normal, angle};
    parallel_for(m, 1 << 13, n_threads, geometry_range, &g);
}

void vertex_normals(const int64_t *faces, int64_t m, const double *normal, const double *angle,
                    double *vert)
{
    /* vert (V, 3), zeroed by the caller: angle-weighted sum of each vertex's face normals */
    for (int64_t f = 0; f < m; f++)
        for (int c = 0; c < 3; c++) {
            double *v = vert + 3 * faces[3 * f + c];
            double w = angle[3 * f + c];
            for (int a = 0; a < 3; a++)
                v[a] += w * normal[3 * f + a];
        }
}

int edge_neighbours(const int64_t *faces, int64_t m, int64_t n_vertices, const double *normal,
                    int64_t *neighbour, double **sums_out, int64_t *n_crowded)
{
    /* the face across edge k (corners k, k + 1) of each face: -1 on a boundary edge;
     * -2 - e where three or more faces share the edge, e indexing the sums of their
     * normals (the pseudo-normal of such an edge) */
    int64_t *first = calloc(n_vertices + 1, sizeof(int64_t));
    int64_t *fill = malloc(sizeof(int64_t) * (n_vertices + 1));
    int64_t *slot_other = malloc(sizeof(int64_t) * 3 * m);
    int64_t *slot_edge = malloc(sizeof(int64_t) * 3 * m);  /* 3 face + k of the first face */
    int64_t *slot_count = calloc(3 * m, sizeof(int64_t));
    int64_t *slot_of = malloc(sizeof(int64_t) * 3 * m);
    int64_t *index = NULL;
    double *sums = NULL;
    int status = -1;
    if (!first || !fill || !slot_other || !slot_edge || !slot_count || !slot_of)
        goto done;
    /* edges grouped by their smaller vertex (a counting sort), then matched in-bucket */
    for (int64_t f = 0; f < m; f++)
        for (int k = 0; k < 3; k++) {
            int64_t a = faces[3 * f + k], b = faces[3 * f + (k + 1) % 3];
            first[(a < b ? a : b) + 1]++;
        }
    for (int64_t v = 0; v < n_vertices; v++)
        first[v + 1] += first[v];
    memcpy(fill, first, sizeof(int64_t) * n_vertices);
    for (int64_t i = 0; i < 3 * m; i++)
        neighbour[i] = -1;
    int64_t crowded = 0;
    for (int64_t f = 0; f < m; f++)
        for (int k = 0; k < 3; k++) {
            int64_t a = faces[3 * f + k], b = faces[3 * f + (k + 1) % 3];
            if (a > b) {
                int64_t s = a;
                a = b, b = s;
            }
            int64_t s = first[a];
            while (s < fill[a] && slot_other[s] != b)
                s++;
            if (s == fill[a]) {
                slot_other[s] = b;
                slot_edge[s] = 3 * f + k;
                fill[a]++;
            } else if (slot_count[s] == 1) {
                int64_t g = slot_edge[s];
                neighbour[3 * f + k] = g / 3;
                neighbour[g] = f;  /* row g / 3, column g % 3 */
            }
            slot_count[s]++;
            if (slot_count[s] == 3)
                crowded++;
            slot_of[3 * f + k] = s;
        }
    sums = calloc(crowded > 0 ? 3 * crowded : 1, sizeof(double));
    if (sums == NULL)
        goto done;
    if (crowded) {
        index = malloc(sizeof(int64_t) * 3 * m);
        if (index == NULL)
            goto done;
        for (int64_t i = 0; i < 3 * m; i++)
            index[i] = -1;
        int64_t e = 0;
        for (int64_t f = 0; f < m; f++)
            for (int k = 0; k < 3; k++) {
                int64_t s = slot_of[3 * f + k];
                if (slot_count[s] < 3)
                    continue;
                if (index[s] < 0)
                    index[s] = e++;
                for (int c = 0; c < 3; c++)
                    sums[3 * index[s] + c] += normal[3 * f + c];
                neighbour[3 * f + k] = -2 - index[s];
            }
    }
    *sums_out = sums;
    *n_crowded = crowded;
    sums = NULL;
    status = 0;
done:
    free(first);
    free(fill);
    free(slot_other);
    free(slot_edge);
    free(slot_count);
    free(slot_of);
    free(index);
    free(sums);
    return status;
}
