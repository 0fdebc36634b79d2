/* The names of a .msh file's $PhysicalNames section that gmsh's API drops:
   gmsh keeps one physical group per name and dimension, so a second group of
   the same dimension and name ("tissue" for volume groups 1 and 2) came back
   unnamed and became physical_3_2, a material and set of its own that
   --material tissue did not reach. The section is read here (text in every
   MSH version, binary files included: `dim tag "name"` lines) and an unnamed
   group is given its name from the file; groups that share a name then make
   one set and one material (lib/mesh/import.c). Runs in gmsh's child
   (gmsh_read.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_gmsh.h"

/* the next line of in into buf (at most n - 1 bytes, the rest of a longer
   line dropped); 0 at the end of the file */
static int next_line(FILE *in, char *buf, int n)
{
    if (!fgets(buf, n, in)) return 0;
    size_t len = strlen(buf);
    if (len && buf[len - 1] != '\n') { /* too long: skip to its end */
        int ch;
        while ((ch = fgetc(in)) != EOF && ch != '\n') continue;
    }
    return 1;
}

int aug_physical_names(const char *path, aug_tagged *t, aug_err *e)
{
    (void)e;
    int unnamed = 0;
    for (int i = 0; i < t->ngroup; i++) unnamed |= !t->groups[i].name[0];
    if (!unnamed) return 0;
    FILE *in = fopen(path, "rb");
    if (!in) return 0; /* gmsh read it; its names stand */
    char line[512];
    int found = 0;
    while (!found && next_line(in, line, sizeof line)) {
        found = !strncmp(line, "$PhysicalNames", 14);
        /* past the sections that may hold names: $Nodes comes after them */
        if (!strncmp(line, "$Nodes", 6) || !strncmp(line, "$Entities", 9)) break;
    }
    long cnt = 0;
    if (found && next_line(in, line, sizeof line)) cnt = strtol(line, NULL, 10);
    for (long k = 0; k < cnt && next_line(in, line, sizeof line); k++) {
        int dim, tag, off = 0;
        if (sscanf(line, "%d %d %n", &dim, &tag, &off) != 2 || line[off] != '"') break;
        const char *s = line + off + 1, *q = strchr(s, '"');
        if (!q || q == s || (size_t)(q - s) >= AUG_NAME) continue; /* gmsh's own rules apply to the rest */
        for (int i = 0; i < t->ngroup; i++) {
            aug_tagged_group *g = &t->groups[i];
            if (g->dim == dim && g->tag == tag && !g->name[0]) {
                memcpy(g->name, s, (size_t)(q - s));
                g->name[q - s] = 0;
            }
        }
    }
    fclose(in);
    return 0;
}
