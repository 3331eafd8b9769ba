/* Embree 3's packet intersection rate on raypack's sphere-grid scenes, the
 * reference of the whole-process cast comparison in docs/performance.md.
 *
 * Reads the `v` block and the `s` lines of an NFF file (what
 * scripts/grid-scenes.py writes: a camera and spheres), builds an Embree
 * scene of native spheres (RTC_GEOMETRY_TYPE_SPHERE_POINT), and casts one
 * primary ray per pixel through the pixel centre with raypack's camera
 * convention (README: vertical field of view, sx = (2(i+1/2)/W - 1)
 * tan(vfov/2) W/H, sy = (1 - 2(j+1/2)/H) tan(vfov/2)), in tiles of 2x2
 * (rtcIntersect4), 4x2 (rtcIntersect8) and 4x4 (rtcIntersect16) pixels, the
 * shapes raypack's packets of 4, 8 and 16 take, with the coherent-ray
 * context flag. The directions are computed once, before timing; the timed
 * loop fills the packets and intersects (no shading, no image): Embree's
 * intersection-only packet rate. The scene build
 * is reported apart. Each width runs ROUNDS times, interleaved; the best and
 * median round are printed, with a checksum of the hit id of each pixel (so
 * the loop cannot be optimized away; the same at every width).
 *
 * Build (Debian: apt-get install libembree-dev; Embree 3.13):
 *     cc -O2 -o /tmp/embree_grid tools/embree_grid.c -lembree3 -lm
 * Run:
 *     python3 scripts/grid-scenes.py /tmp/grids 16 64 256
 *     /tmp/embree_grid /tmp/grids/grid-64.nff 1024 1024 [ROUNDS]
 * Embree uses every core unless told otherwise; the measurement runs on one
 * thread (the device is created with "threads=1", and the ray loop is this
 * program's single thread).
 */
#include <embree3/rtcore.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_ROUNDS 64

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

typedef struct {
    float eye[3], at[3], up[3], vfov;
} View;

static void sub3(const float *a, const float *b, float *o) {
    for (int i = 0; i < 3; i++) o[i] = a[i] - b[i];
}
static void cross3(const float *a, const float *b, float *o) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static void norm3(float *a) {
    float l = sqrtf(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int i = 0; i < 3; i++) a[i] /= l;
}

/* The camera frame: forward f, right r, up u (unit). */
typedef struct {
    float eye[3], f[3], r[3], u[3], sx_scale, sy_scale;
} Cam;

static Cam camera(const View *v, int w, int h) {
    Cam c;
    memcpy(c.eye, v->eye, sizeof c.eye);
    sub3(v->at, v->eye, c.f);
    norm3(c.f);
    cross3(c.f, v->up, c.r);
    norm3(c.r);
    cross3(c.r, c.f, c.u);
    float t = tanf(v->vfov * (float)M_PI / 360.0f);
    c.sy_scale = t;
    c.sx_scale = t * (float)w / (float)h;
    return c;
}

/* Reads the camera and the spheres (x y z r, as float4) of an NFF file. */
static float *read_nff(const char *path, View *view, size_t *count) {
    FILE *f = fopen(path, "r");
    if (!f) {
        perror(path);
        exit(1);
    }
    size_t cap = 1024, n = 0;
    float *s = malloc(cap * 4 * sizeof(float));
    char line[512];
    int have_view = 0;
    while (fgets(line, sizeof line, f)) {
        float a, b, c, d;
        if (sscanf(line, "from %f %f %f", &a, &b, &c) == 3) {
            view->eye[0] = a, view->eye[1] = b, view->eye[2] = c;
        } else if (sscanf(line, "at %f %f %f", &a, &b, &c) == 3) {
            view->at[0] = a, view->at[1] = b, view->at[2] = c;
        } else if (sscanf(line, "up %f %f %f", &a, &b, &c) == 3) {
            view->up[0] = a, view->up[1] = b, view->up[2] = c;
        } else if (sscanf(line, "angle %f", &a) == 1) {
            view->vfov = a;
            have_view = 1;
        } else if (sscanf(line, "s %f %f %f %f", &a, &b, &c, &d) == 4) {
            if (n == cap) {
                cap *= 2;
                s = realloc(s, cap * 4 * sizeof(float));
            }
            s[4 * n] = a, s[4 * n + 1] = b, s[4 * n + 2] = c, s[4 * n + 3] = d;
            n++;
        }
    }
    fclose(f);
    if (!have_view || n == 0) {
        fprintf(stderr, "%s: no camera or no spheres\n", path);
        exit(1);
    }
    *count = n;
    return s;
}

/* The unit direction through the centre of every pixel, row-major (made
 * once, outside the timed loops: only the packets are filled per frame). */
static float *directions(const Cam *c, int w, int h) {
    float *dirs = malloc((size_t)w * h * 3 * sizeof(float));
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            float sx = (2.0f * (i + 0.5f) / w - 1.0f) * c->sx_scale;
            float sy = (1.0f - 2.0f * (j + 0.5f) / h) * c->sy_scale;
            float *d = dirs + 3 * ((size_t)j * w + i);
            for (int a = 0; a < 3; a++) d[a] = c->f[a] + sx * c->r[a] + sy * c->u[a];
            norm3(d);
        }
    return dirs;
}

/* One frame of W x H primary rays in tiles of TW x TH, with rtcIntersectN.
 * Returns a checksum of the hit ids by pixel (the same at every width). (A macro so that each width has its
 * own loop over its own packet type.) */
#define FRAME(N, TW, TH, FN)                                                                 \
    static unsigned frame##N(RTCScene scene, const Cam *c, const float *dirs, int w, int h) { \
        struct RTCIntersectContext ctx;                                                      \
        rtcInitIntersectContext(&ctx);                                                       \
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;                                     \
        unsigned sum = 0;                                                                    \
        for (int y0 = 0; y0 < h; y0 += TH)                                                   \
            for (int x0 = 0; x0 < w; x0 += TW) {                                             \
                struct RTCRayHit##N rh;                                                      \
                int valid[N], pix[N];                                                        \
                for (int k = 0; k < N; k++) {                                                \
                    int i = x0 + k % TW, j = y0 + k / TW;                                    \
                    valid[k] = (i < w && j < h) ? -1 : 0;                                    \
                    pix[k] = j * w + i;                                                      \
                    const float *d = dirs + 3 * (size_t)(valid[k] ? pix[k] : 0);           \
                    rh.ray.org_x[k] = c->eye[0];                                             \
                    rh.ray.org_y[k] = c->eye[1];                                             \
                    rh.ray.org_z[k] = c->eye[2];                                             \
                    rh.ray.dir_x[k] = d[0];                                                  \
                    rh.ray.dir_y[k] = d[1];                                                  \
                    rh.ray.dir_z[k] = d[2];                                                  \
                    rh.ray.tnear[k] = 0.0f;                                                  \
                    rh.ray.tfar[k] = INFINITY;                                               \
                    rh.ray.time[k] = 0.0f;                                                   \
                    rh.ray.mask[k] = 0xFFFFFFFFu;                                            \
                    rh.ray.flags[k] = 0;                                                     \
                    rh.ray.id[k] = k;                                                        \
                    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;                              \
                    rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;                              \
                    rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;                           \
                }                                                                            \
                FN(valid, scene, &ctx, &rh);                                                 \
                for (int k = 0; k < N; k++)                                                  \
                    if (valid[k]) sum += (rh.hit.primID[k] + 1u) * (2u * pix[k] + 1u);       \
            }                                                                                \
        return sum;                                                                          \
    }

FRAME(4, 2, 2, rtcIntersect4)
FRAME(8, 4, 2, rtcIntersect8)
FRAME(16, 4, 4, rtcIntersect16)

int main(int argc, char **argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: %s SCENE.nff WIDTH HEIGHT [ROUNDS]\n", argv[0]);
        return 2;
    }
    int w = atoi(argv[2]), h = atoi(argv[3]);
    int rounds = argc > 4 ? atoi(argv[4]) : 5;
    if (w < 1 || h < 1 || rounds < 1 || rounds > MAX_ROUNDS) {
        fprintf(stderr, "bad size or rounds (1..%d)\n", MAX_ROUNDS);
        return 2;
    }
    View view;
    size_t n;
    float *spheres = read_nff(argv[1], &view, &n);
    Cam cam = camera(&view, w, h);
    float *dirs = directions(&cam, w, h);

    double t0 = now();
    RTCDevice dev = rtcNewDevice("threads=1");
    RTCScene scene = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), n);
    memcpy(v, spheres, n * 4 * sizeof(float));
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    double build = now() - t0;
    if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) {
        fprintf(stderr, "embree error %d\n", rtcGetDeviceError(dev));
        return 1;
    }

    int widths[3] = {4, 8, 16};
    double times[3][MAX_ROUNDS];
    unsigned sums[3] = {0, 0, 0};
    for (int r = 0; r < rounds; r++)
        for (int k = 0; k < 3; k++) {
            double s = now();
            unsigned sum = k == 0 ? frame4(scene, &cam, dirs, w, h)
                             : k == 1 ? frame8(scene, &cam, dirs, w, h)
                                      : frame16(scene, &cam, dirs, w, h);
            times[k][r] = now() - s;
            sums[k] = sum;
        }
    double rays = (double)w * h;
    printf("# embree %d.%d.%d scene=%s spheres=%zu size=%dx%d rounds=%d build_ms=%.3f\n", RTC_VERSION_MAJOR,
           RTC_VERSION_MINOR, RTC_VERSION_PATCH, argv[1], n, w, h, rounds, build * 1e3);
    for (int k = 0; k < 3; k++) {
        qsort(times[k], rounds, sizeof(double), cmp_double);
        double best = times[k][0], median = times[k][rounds / 2];
        printf("embree packet=%d best_s=%.6f median_s=%.6f mrays_best=%.3f mrays_median=%.3f ids=%08x\n", widths[k],
               best, median, rays / best / 1e6, rays / median / 1e6, sums[k]);
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(dev);
    free(spheres);
    free(dirs);
    return 0;
}
