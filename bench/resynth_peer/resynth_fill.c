/*
 * resynth_fill: benchmark-only driver for the Resynthesizer engine (Harrison's per-pixel texture
 * synthesis, as shipped in GIMP's Resynthesizer plug-in). Our own code; the engine is built from
 * its upstream source by build.sh at benchmark time and is never part of this repository.
 *
 *   resynth_fill SAMPLE.png OUT.png WIDTH HEIGHT [--seed S] [--coords PATH]
 *                [--patch N] [--probes N] [--context T] [--outliers F]
 *
 * Makes a WIDTHxHEIGHT RGB canvas, puts SAMPLE at its top-left corner, selects the rest (mask
 * 0xFF) as the target and calls the engine's simple API, imageSynth(), whose corpus is the
 * unselected part, i.e. the sample. Writes OUT.png (8-bit RGB) and, by default, OUT with its
 * ".png" replaced by ".coords": raw little-endian float32, WIDTH*HEIGHT*2 values, row-major,
 * (x, y) of the sample texel that each output pixel was copied from (sample pixels map to
 * themselves; -1 where the engine left a pixel without a source). The coordinates come from the
 * engine's own per-target "sourceOfMap", handed to resynth_peer_sources() by a one-line hook
 * that build.sh adds to engine.c. Engine time (imageSynth only, no PNG I/O) goes to stderr.
 */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "glibProxy.h"
#include "imageSynth.h"
#include "map.h"

unsigned int resynth_peer_seed = 1198472; /* the engine's own fixed seed, the default */
static float *coords;                     /* W*H*2, filled by the hook */
static int coords_seen;

/* Called by the patched engine() after refinement, before it frees its sourceOfMap. */
void resynth_peer_sources(const void *source_of_map) {
  const Map *m = source_of_map;
  if (!coords) return;
  for (guint i = 0; i < m->width * m->height; i++) {
    Coordinates c = g_array_index(m->data, Coordinates, i);
    coords[2 * i] = (float)c.x;
    coords[2 * i + 1] = (float)c.y;
  }
  coords_seen = 1;
}

static void no_progress(int percent, void *context) { (void)percent; (void)context; }

static void die(const char *msg) {
  fprintf(stderr, "resynth_fill: %s\n", msg);
  exit(1);
}

int main(int argc, char **argv) {
  if (argc < 5)
    die("usage: resynth_fill SAMPLE.png OUT.png WIDTH HEIGHT [--seed S] [--coords PATH] "
        "[--patch N] [--probes N] [--context T] [--outliers F]");
  const char *in_path = argv[1], *out_path = argv[2];
  int width = atoi(argv[3]), height = atoi(argv[4]);
  if (width <= 0 || height <= 0) die("WIDTH and HEIGHT must be positive");

  TImageSynthParameters params;
  setDefaultParams(&params); /* patch 30, probes 200, context 1, outliers 0.117, map 0.5 */
  char *coords_path = NULL;
  for (int i = 5; i < argc; i++) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (!v) die("option without a value");
    if (!strcmp(a, "--seed")) resynth_peer_seed = (unsigned)strtoul(v, NULL, 10);
    else if (!strcmp(a, "--coords")) coords_path = strdup(v);
    else if (!strcmp(a, "--patch")) params.patchSize = (unsigned)atoi(v);
    else if (!strcmp(a, "--probes")) params.maxProbeCount = (unsigned)atoi(v);
    else if (!strcmp(a, "--context")) params.matchContextType = atoi(v);
    else if (!strcmp(a, "--outliers")) params.sensitivityToOutliers = atof(v);
    else die("unknown option");
    i++;
  }
  if (!coords_path) {
    size_t n = strlen(out_path);
    coords_path = malloc(n + 8);
    strcpy(coords_path, out_path);
    if (n > 4 && !strcmp(out_path + n - 4, ".png")) coords_path[n - 4] = '\0';
    strcat(coords_path, ".coords");
  }

  png_image sample;
  memset(&sample, 0, sizeof sample);
  sample.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&sample, in_path)) die(sample.message);
  sample.format = PNG_FORMAT_RGB; /* any PNG to 8-bit RGB (alpha composited on black) */
  int sw = (int)sample.width, sh = (int)sample.height;
  if (sw > width || sh > height) die("the sample is larger than the canvas");
  unsigned char *pixels = malloc(PNG_IMAGE_SIZE(sample));
  if (!png_image_finish_read(&sample, NULL, pixels, 0, NULL)) die(sample.message);

  size_t n = (size_t)width * height;
  unsigned char *canvas = calloc(n, 3), *mask = malloc(n);
  memset(mask, 0xFF, n); /* 0xFF: to synthesize */
  for (int y = 0; y < sh; y++) {
    memcpy(canvas + (size_t)y * width * 3, pixels + (size_t)y * sw * 3, (size_t)sw * 3);
    memset(mask + (size_t)y * width, 0, (size_t)sw); /* 0: the sample, i.e. the corpus */
  }
  coords = malloc(n * 2 * sizeof(float));
  for (size_t i = 0; i < n * 2; i++) coords[i] = -1.0f;

  ImageBuffer image = {canvas, (unsigned)width, (unsigned)height, (size_t)width * 3};
  ImageBuffer mask_buffer = {mask, (unsigned)width, (unsigned)height, (size_t)width};
  int cancel = 0;
  struct timespec t0, t1;
  clock_gettime(CLOCK_MONOTONIC, &t0);
  int error = imageSynth(&image, &mask_buffer, T_RGB, &params, no_progress, NULL, &cancel);
  clock_gettime(CLOCK_MONOTONIC, &t1);
  if (error) {
    fprintf(stderr, "resynth_fill: imageSynth error %d\n", error);
    return 1;
  }
  fprintf(stderr, "resynth_fill: engine %.3f s (%dx%d from %dx%d, seed %u)\n",
          (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec), width, height, sw, sh,
          resynth_peer_seed);

  png_image out;
  memset(&out, 0, sizeof out);
  out.version = PNG_IMAGE_VERSION;
  out.width = (png_uint_32)width;
  out.height = (png_uint_32)height;
  out.format = PNG_FORMAT_RGB;
  if (!png_image_write_to_file(&out, out_path, 0, canvas, width * 3, NULL)) die(out.message);

  if (!coords_seen) {
    fprintf(stderr, "resynth_fill: the engine hook did not run; no %s written\n", coords_path);
    return 1;
  }
  size_t unsourced = 0;
  for (int y = 0; y < height; y++)
    for (int x = 0; x < width; x++) {
      float *c = coords + 2 * ((size_t)y * width + x);
      if (x < sw && y < sh) c[0] = (float)x, c[1] = (float)y; /* sample pixels: themselves */
      else if (c[0] < 0) unsourced++;
    }
  if (unsourced) fprintf(stderr, "resynth_fill: %zu target pixels have no source\n", unsourced);
  FILE *f = fopen(coords_path, "wb");
  if (!f || fwrite(coords, sizeof(float), n * 2, f) != n * 2 || fclose(f)) die("cannot write coords");
  return 0;
}
