/* formats/stream.md's record table and lib/stream/stream.c's table agree row by row. */
#include <string.h>
#include "augcut.h"
#include "t.h"

static uint64_t parse_len(const char *s)
{
    if (!strcmp(s, "2^40")) return (uint64_t)1 << 40;
    char *end;
    uint64_t v = strtoull(s, &end, 10);
    if (!strcmp(end, " MiB")) v <<= 20;
    return v;
}

static void trim(char *s)
{
    size_t n = strlen(s);
    while (n > 0 && s[n - 1] == ' ') s[--n] = 0;
}

static void test_table_matches_spec(void)
{
    const char *root = getenv("AUG_ROOT");
    char path[4096];
    snprintf(path, sizeof path, "%.4000s/formats/stream.md", root ? root : ".");
    FILE *f = fopen(path, "r");
    T_CHECK(f != NULL, "cannot open formats/stream.md (AUG_ROOT)");
    if (!f) return;
    char line[1024];
    int in_table = 0, rows = 0;
    while (fgets(line, sizeof line, f)) {
        if (strstr(line, "### 3.3 Record table")) in_table = 1;
        else if (in_table && line[0] == '#') break;
        if (!in_table || line[0] != '|' || strncmp(line, "| type", 6) == 0 || line[1] == '-')
            continue;
        char type[8], phase[8], once[8], per[8], mn[32], mx[32];
        if (sscanf(line, "| %7[^ |] | %7[^ |] | %7[^ |] | %7[^ |] | %31[^|]| %31[^|]|", type,
                   phase, once, per, mn, mx) != 6)
            continue;
        trim(mn);
        trim(mx);
        const aug_rectype *t = aug_rectype_find(type);
        T_CHECK(t != NULL, "spec row %s missing from lib/stream/stream.c", type);
        if (!t) continue;
        rows++;
        int ph = !strcmp(phase, "any") ? -1 : atoi(phase);
        T_CHECK(t->phase == ph, "%s: phase %d in code, %s in spec", type, t->phase, phase);
        T_CHECK(t->once == !strcmp(once, "yes"), "%s: once differs", type);
        T_CHECK(t->perstep == !strcmp(per, "yes"), "%s: per-step differs", type);
        T_CHECK(t->minlen == parse_len(mn), "%s: min %llu in code, %s in spec", type,
                (unsigned long long)t->minlen, mn);
        T_CHECK(t->maxlen == parse_len(mx), "%s: max %llu in code, %s in spec", type,
                (unsigned long long)t->maxlen, mx);
        /* the codec column: the last cell, `lib/LAYER/FILE.c`, names the file of the
           codec bound in the table, and that file exists */
        char *tick = strrchr(line, '`'), *open = NULL;
        if (tick) {
            *tick = 0;
            open = strrchr(line, '`');
        }
        T_CHECK(open != NULL, "%s: no codec column in spec", type);
        if (!open) continue;
        T_CHECK(t->codec && !strcmp(t->codec->file, open + 1), "%s: codec %s in code, %s in spec",
                type, t->codec ? t->codec->file : "(none)", open + 1);
        char fp[4200];
        snprintf(fp, sizeof fp, "%.4000s/%s", root ? root : ".", open + 1);
        FILE *cf = fopen(fp, "r");
        T_CHECK(cf != NULL, "%s: codec file %s missing", type, open + 1);
        if (cf) fclose(cf);
    }
    fclose(f);
    int n = 0;
    while (aug_rectype_at(n)) n++;
    T_CHECK(rows == n, "spec table has %d rows, code %d", rows, n);
}

/* property bits follow the letter case of every type in the table */
static void test_property_bits(void)
{
    for (size_t i = 0; aug_rectype_at(i); i++) {
        const char *t = aug_rectype_at(i)->type;
        T_CHECK(aug_type_critical(t) == (t[0] >= 'A' && t[0] <= 'Z'), "%s", t);
        T_CHECK(t[2] >= 'A' && t[2] <= 'Z', "%s: third letter must be upper case", t);
    }
    T_CHECK(aug_type_safe_to_copy("pROv") && !aug_type_safe_to_copy("FACT"), "safe-to-copy");
}

int main(void)
{
    T_RUN(test_table_matches_spec);
    T_RUN(test_property_bits);
    T_EXIT();
}
