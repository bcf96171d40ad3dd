/* mem.c - memset and memcpy for the freestanding firmware: GCC may emit calls to them for struct
 * initialisation and copies even with -ffreestanding (there is no C library on the core). Word
 * copies when both pointers and the length allow it (the struct copies of the control step: a quarter
 * of its cycles went into a byte loop). */
#include <stddef.h>
#include <stdint.h>

void *memset(void *dst, int c, size_t n);
void *memcpy(void *dst, const void *src, size_t n);

void *memset(void *dst, int c, size_t n)
{
    if ((((uintptr_t)dst | n) & 3u) == 0) { /* fw_init clears the control state in place: word stores */
        uint32_t *dw = dst, w = (unsigned char)c * 0x01010101u;
        for (n >>= 2; n; n--)
            *dw++ = w;
        return dst;
    }
    unsigned char *d = dst;
    while (n--)
        *d++ = (unsigned char)c;
    return dst;
}

void *memcpy(void *dst, const void *src, size_t n)
{
    if ((((uintptr_t)dst | (uintptr_t)src | n) & 3u) == 0) {
        uint32_t *dw = dst;
        const uint32_t *sw = src;
        for (n >>= 2; n; n--)
            *dw++ = *sw++;
        return dst;
    }
    unsigned char *d = dst;
    const unsigned char *s = src;
    while (n--)
        *d++ = *s++;
    return dst;
}
