/* A game loop on libsweep's C interface: open a character once, then each frame give the body's
 * pose, now and then a hit, advance by the frame time and read the positions back — as an engine
 * that draws the mesh under the body's transform itself: only the vertices the parts bind, in the
 * mesh's own space (sweep_bound_positions), into a buffer that keeps the others at rest. (An engine
 * that wants every vertex in world space reads sweep_positions instead.)
 *
 *   sweep-capi-example RIG BINDING MESH.obj [SETTINGS.scene.json]
 *
 * MESH.obj stands for the engine's own mesh: only its `v` lines are read, in order. The body walks
 * along x and turns while the frame time varies (1/60 s, 1/144 s, 1/30 s); a hit lands on the first
 * part after half a second. Prints the largest distance of a vertex from the rigidly moved rest
 * mesh (the parts' lag and swing; in the mesh's space, from its rest) every 30 frames. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sweep/sweep.h"

/* The `v` lines of an OBJ, as floats; NULL if the file cannot be read. */
static float* read_obj_vertices(const char* path, int* count) {
  FILE* f = fopen(path, "r");
  if (!f) return NULL;
  int capacity = 1024, n = 0;
  float* xyz = malloc(sizeof(float) * 3 * (size_t)capacity);
  char line[512];
  while (xyz && fgets(line, sizeof line, f)) {
    float x, y, z;
    if (line[0] != 'v' || line[1] != ' ' || sscanf(line + 2, "%f %f %f", &x, &y, &z) != 3) continue;
    if (n == capacity) {
      capacity *= 2;
      float* grown = realloc(xyz, sizeof(float) * 3 * (size_t)capacity);
      if (!grown) free(xyz);
      xyz = grown;
      if (!xyz) break;
    }
    xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z;
    ++n;
  }
  fclose(f);
  *count = n;
  return xyz;
}

int main(int argc, char** argv) {
  if (argc < 4 || argc > 5) {
    fprintf(stderr, "usage: %s RIG BINDING MESH.obj [SETTINGS.scene.json]\n", argv[0]);
    return 1;
  }
  int count = 0;
  float* rest = read_obj_vertices(argv[3], &count);
  if (!rest || count == 0) {
    fprintf(stderr, "error: %s: no vertices read\n", argv[3]);
    free(rest);
    return 2;
  }
  sweep_instance* dino = sweep_open(argv[1], argv[2], argc == 5 ? argv[4] : NULL, rest, count);
  if (!dino) {
    fprintf(stderr, "error: %s\n", sweep_last_error());
    free(rest);
    return 2;
  }
  /* The mesh as the engine keeps it, in its own space: the rest positions, of which the bound
   * vertices are updated each frame. */
  float* out = malloc(sizeof(float) * 3 * (size_t)count);
  if (out) memcpy(out, rest, sizeof(float) * 3 * (size_t)count);
  const int bound = sweep_bound_count(dino); /* the vertices the parts move, read once */
  int* index = bound > 0 ? malloc(sizeof(int) * (size_t)bound) : NULL;
  float* moved = bound > 0 ? malloc(sizeof(float) * 3 * (size_t)bound) : NULL;
  if (bound < 0 || (bound > 0 && (!index || !moved || sweep_bound_indices(dino, index) != 0))) {
    fprintf(stderr, "error: %s\n", bound < 0 ? sweep_last_error() : "out of memory");
    free(out), free(index), free(moved), free(rest);
    sweep_close(dino);
    return 2;
  }
  const double frame_times[] = {1.0 / 60, 1.0 / 144, 1.0 / 30};
  double t = 0;
  int code = 0, hit = 0;
  for (int frame = 1; frame <= 240 && out; ++frame) {
    const double dt = frame_times[frame % 3];
    /* Where the body will be at the end of this frame: walking along x, turning about y. */
    const double a = 0.3 * sin(2.0 * (t + dt)), c = cos(a), s = sin(a);
    const double pose[16] = {c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, 0.2 * (t + dt), 0, 0, 1};
    code = sweep_set_body(dino, pose);
    if (code == 0 && t >= 0.5 && !hit) {
      /* A hit: 0.05 s of push at the first vertex (on a part or not: the nearest surface point). */
      const double point[3] = {rest[0], rest[1], rest[2]}, force[3] = {0, 0, 5};
      /* The rig's first part: a real game knows its parts' names. */
      code = sweep_add_force(dino, "tube", point, force, 0.05);
      if (code == SWEEP_ERROR_USAGE) code = 0; /* not a rig with a part "tube": no hit */
      hit = 1;
    }
    if (code == 0) code = sweep_advance(dino, dt);
    if (code == 0 && bound > 0) code = sweep_bound_positions(dino, moved);
    if (code != 0) break;
    for (int i = 0; i < bound; ++i) memcpy(out + 3 * index[i], moved + 3 * i, sizeof(float) * 3);
    /* (The engine draws `out` under the body's pose, `pose`, as its object's transform.) */
    t += dt;
    if (frame % 30 == 0) {
      double largest = 0;
      for (int v = 0; v < count; ++v) {
        const double d = sqrt(pow(out[3 * v] - rest[3 * v], 2) + pow(out[3 * v + 1] - rest[3 * v + 1], 2) +
                              pow(out[3 * v + 2] - rest[3 * v + 2], 2));
        if (d > largest) largest = d;
      }
      printf("frame %d  t = %.4f s  largest lag %.6g\n", frame, t, largest);
    }
  }
  if (code != 0) fprintf(stderr, "error (%d): %s\n", code, sweep_last_error());
  free(out);
  free(index);
  free(moved);
  free(rest);
  sweep_close(dino);
  return code;
}
