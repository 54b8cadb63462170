/* Native Embree on the view of `cargo bench --bench mesh`, for comparison (not run by CI).
 *
 * Embree 3 from Debian (`apt-get install libembree-dev`; the Python binding benches/embree.py
 * uses is Embree 4, whose wheel has no C headers). The mesh comes from benches/embree.py
 * (`--dump FILE`: the same icosphere as raytree's); the camera is sphere_scene's: at (0, 0, 3)
 * looking at the origin, 40 degrees vertical field of view, one ray through each pixel centre.
 * One thread traces; modes: rtcIntersect1 per ray (row-major), and rtcIntersect4/8/16 packets
 * over 2x2, 4x2 and 4x4 pixel tiles.
 *
 *   python3 benches/embree.py 8 --dump /tmp/ico8.bin
 *   gcc -O2 -o /tmp/embree_native benches/embree_native.c -lembree3 -lm
 *   taskset -c 0 /tmp/embree_native /tmp/ico8.bin 512
 */
#include <embree3/rtcore.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* The pixel-centre ray direction of pixel (x, y) of a size x size image. */
static void direction(int x, int y, int size, float d[3]) {
    double half = tan(40.0 * M_PI / 180.0 / 2.0);
    double u = ((x + 0.5) / size * 2.0 - 1.0) * half;
    double v = (1.0 - (y + 0.5) / size * 2.0) * half;
    double n = sqrt(u * u + v * v + 1.0);
    d[0] = (float)(u / n);
    d[1] = (float)(v / n);
    d[2] = (float)(-1.0 / n);
}

static long single(RTCScene scene, int size) {
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    long hits = 0;
    for (int y = 0; y < size; y++) {
        for (int x = 0; x < size; x++) {
            struct RTCRayHit rh;
            float d[3];
            direction(x, y, size, d);
            rh.ray.org_x = 0.0f;
            rh.ray.org_y = 0.0f;
            rh.ray.org_z = 3.0f;
            rh.ray.dir_x = d[0];
            rh.ray.dir_y = d[1];
            rh.ray.dir_z = d[2];
            rh.ray.tnear = 0.0f;
            rh.ray.tfar = INFINITY;
            rh.ray.time = 0.0f;
            rh.ray.mask = 0xFFFFFFFFu;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    }
    return hits;
}

/* Packets of W = TW x TH rays over tiles; SoA layouts of RTCRayHit4/8/16 share one shape. */
#define PACKET_FN(NAME, W, TW, TH, TYPE, CALL)                                             \
    static long NAME(RTCScene scene, int size) {                                          \
        struct RTCIntersectContext ctx;                                                        \
        rtcInitIntersectContext(&ctx);                                                    \
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;                                  \
        long hits = 0;                                                                    \
        for (int y0 = 0; y0 < size; y0 += TH) {                                           \
            for (int x0 = 0; x0 < size; x0 += TW) {                                       \
                TYPE rh __attribute__((aligned(64)));                                     \
                int valid[W] __attribute__((aligned(64)));                                \
                for (int i = 0; i < W; i++) {                                             \
                    int x = x0 + i % TW, y = y0 + i / TW;                                 \
                    float d[3];                                                           \
                    valid[i] = (x < size && y < size) ? -1 : 0;                           \
                    direction(x, y, size, d);                                             \
                    rh.ray.org_x[i] = 0.0f;                                               \
                    rh.ray.org_y[i] = 0.0f;                                               \
                    rh.ray.org_z[i] = 3.0f;                                               \
                    rh.ray.dir_x[i] = d[0];                                               \
                    rh.ray.dir_y[i] = d[1];                                               \
                    rh.ray.dir_z[i] = d[2];                                               \
                    rh.ray.tnear[i] = 0.0f;                                               \
                    rh.ray.tfar[i] = INFINITY;                                            \
                    rh.ray.time[i] = 0.0f;                                                \
                    rh.ray.mask[i] = 0xFFFFFFFFu;                                         \
                    rh.ray.id[i] = 0;                                                     \
                    rh.ray.flags[i] = 0;                                                  \
                    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;                           \
                }                                                                         \
                CALL(valid, scene, &ctx, &rh);                                            \
                for (int i = 0; i < W; i++)                                               \
                    hits += valid[i] && rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;      \
            }                                                                             \
        }                                                                                 \
        return hits;                                                                      \
    }

PACKET_FN(packets4, 4, 2, 2, struct RTCRayHit4, rtcIntersect4)
PACKET_FN(packets8, 8, 4, 2, struct RTCRayHit8, rtcIntersect8)
PACKET_FN(packets16, 16, 4, 4, struct RTCRayHit16, rtcIntersect16)

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: %s MESH.bin SIZE [SIZE...]\n", argv[0]);
        return 2;
    }
    FILE *f = fopen(argv[1], "rb");
    uint32_t nv, nf;
    if (!f || fread(&nv, 4, 1, f) != 1 || fread(&nf, 4, 1, f) != 1) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 2;
    }
    RTCDevice device = rtcNewDevice(NULL);
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), nv);
    uint32_t *ix = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                           3 * sizeof(uint32_t), nf);
    if (fread(v, 12, nv, f) != nv || fread(ix, 12, nf, f) != nf) {
        fprintf(stderr, "short file %s\n", argv[1]);
        return 2;
    }
    fclose(f);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    struct {
        const char *name;
        long (*run)(RTCScene, int);
    } modes[] = {{"rtcIntersect1", single},
                 {"rtcIntersect4 (2x2)", packets4},
                 {"rtcIntersect8 (4x2)", packets8},
                 {"rtcIntersect16 (4x4)", packets16}};
    for (int a = 2; a < argc; a++) {
        int size = atoi(argv[a]);
        for (int m = 0; m < 4; m++) {
            double best = INFINITY;
            long hits = 0;
            for (int rep = 0; rep < 7; rep++) {
                double t = now();
                hits = modes[m].run(scene, size);
                double dt = now() - t;
                best = dt < best ? dt : best;
            }
            double n = (double)size * size;
            printf("embree3 native %u triangles %dx%d %-22s hit %.3f, %.1f ns/ray, %.2f M rays/s "
                   "(fastest of 7)\n",
                   nf, size, size, modes[m].name, hits / n, best * 1e9 / n, n / best / 1e6);
        }
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return 0;
}
