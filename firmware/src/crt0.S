/* crt0.S - start-up and trap entry of the hfi_soc firmware (VexRiscv, RV32IM, machine mode).
 *
 * reset (the RAM's first word, the core's reset vector): set sp, clear .bss, point mtvec at trap_entry
 *       (direct mode), call main().
 * trap_entry: saves the caller-saved registers on the current stack; an interrupt (mcause < 0) calls
 *       irq_handler(pending), pending = the external interrupt lines that are enabled and asserted (the
 *       core's CSR 0xFC0); an exception calls exception_handler(mcause, mepc), which does not return.
 *       The core clears mstatus.MIE on entry and restores it with mret, so the handler is not nested.
 *       It runs every control period, so it has a section of its own (.text.trap_entry) that firmware/link.ld
 *       places with the step's shared code: in the direct-mapped instruction cache it then shares no line
 *       with the step's functions (at the RAM's start it did, with whichever lay 16 KiB on). */

#define CSR_IRQ_PENDING 0xFC0

    .option arch, +zicsr        /* CSR instructions; the C stays -march=rv32im (its libgcc) */

    .section .vectors, "ax"
    .globl _start
_start:
    j reset

    .section .text.trap_entry, "ax"
    .balign 64
trap_entry:
    addi sp, sp, -64
    sw ra, 0(sp)
    sw t0, 4(sp)
    sw t1, 8(sp)
    sw t2, 12(sp)
    sw a0, 16(sp)
    sw a1, 20(sp)
    sw a2, 24(sp)
    sw a3, 28(sp)
    sw a4, 32(sp)
    sw a5, 36(sp)
    sw a6, 40(sp)
    sw a7, 44(sp)
    sw t3, 48(sp)
    sw t4, 52(sp)
    sw t5, 56(sp)
    sw t6, 60(sp)
    csrr a0, mcause
    bltz a0, 1f
    csrr a1, mepc
    call exception_handler
1:  csrr a0, CSR_IRQ_PENDING
    call irq_handler
    lw ra, 0(sp)
    lw t0, 4(sp)
    lw t1, 8(sp)
    lw t2, 12(sp)
    lw a0, 16(sp)
    lw a1, 20(sp)
    lw a2, 24(sp)
    lw a3, 28(sp)
    lw a4, 32(sp)
    lw a5, 36(sp)
    lw a6, 40(sp)
    lw a7, 44(sp)
    lw t3, 48(sp)
    lw t4, 52(sp)
    lw t5, 56(sp)
    lw t6, 60(sp)
    addi sp, sp, 64
    mret

    .section .vectors, "ax"
reset:
    la sp, _stack_top
    la t0, _bss_start
    la t1, _bss_end
1:  bgeu t0, t1, 2f
    sw zero, 0(t0)
    addi t0, t0, 4
    j 1b
2:  la t0, trap_entry
    csrw mtvec, t0
    call main
3:  j 3b
