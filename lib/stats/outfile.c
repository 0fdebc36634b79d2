/* The files stats writes (.vtu, .pvd, .mtx) never replace the stream it
   reads: `stats --vtk in.aug in.aug` read the whole stream, then wrote VTK
   XML over it, exit 0; a .pvd series whose step file was named as the input
   did the same. The input is registered once (aug_out_protect); every output
   is created through aug_out_create, which refuses that file by identity
   (device and inode, so other names and links of it too). */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include "aug_stats.h"

static struct {
    int set;
    dev_t dev;
    ino_t ino;
} in_file;

void aug_out_protect(int fd)
{
    struct stat st;
    in_file.set = fd >= 0 && !fstat(fd, &st) && S_ISREG(st.st_mode);
    if (in_file.set) in_file.dev = st.st_dev, in_file.ino = st.st_ino;
}

int aug_out_check(const char *path, aug_err *e)
{
    struct stat st;
    if (in_file.set && !stat(path, &st) && st.st_dev == in_file.dev && st.st_ino == in_file.ino)
        return aug_err_set(e, AUG_EIO, -1, "", "%s: is the input stream, not overwritten", path);
    return 0;
}

FILE *aug_out_create(const char *path, aug_err *e)
{
    if (aug_out_check(path, e)) return NULL;
    FILE *f = fopen(path, "w");
    if (!f) aug_err_set(e, AUG_EIO, -1, "", "%s: %s", path, strerror(errno));
    return f;
}
