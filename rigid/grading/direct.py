"""Call one TODO unit on many packed inputs inside a small Taichi kernel.

``make_direct_kernel(spec, unit)`` returns ``run(inputs, outputs)`` taking numpy
float64 arrays (K, spec.width("inputs")) and (K, spec.width("outputs")) laid
out as ``specs.pack`` does. Ndarray arguments (no fields) keep these kernels
independent of field allocation, so the offline cache serves them across
processes. The loop is serial: K is small and the result must not depend on
thread timing.
"""
import taichi as ti


def make_direct_kernel(spec, unit):
    cin, cout = spec.columns("inputs"), spec.columns("outputs")
    todo = spec.number

    @ti.func
    def arg(a: ti.template(), i, name: ti.template()):
        start, shape = ti.static(cin[name])
        if ti.static(len(shape) == 0):
            return a[i, start]
        elif ti.static(len(shape) == 1):
            return ti.Vector([a[i, start + j] for j in ti.static(range(shape[0]))])
        else:
            return ti.Matrix([[a[i, start + shape[1] * r + c] for c in ti.static(range(shape[1]))]
                              for r in ti.static(range(shape[0]))])

    @ti.func
    def put(o: ti.template(), i, name: ti.template(), value: ti.template()):
        start, shape = ti.static(cout[name])
        if ti.static(len(shape) == 1):
            for j in ti.static(range(shape[0])):
                o[i, start + j] = value[j]
        else:
            for r, c in ti.static(ti.ndrange(shape[0], shape[1])):
                o[i, start + shape[1] * r + c] = value[r, c]

    @ti.kernel
    def run(a: ti.types.ndarray(dtype=ti.f64, ndim=2), o: ti.types.ndarray(dtype=ti.f64, ndim=2)):
        ti.loop_config(serialize=True)
        for i in range(a.shape[0]):
            if ti.static(todo == 1):
                put(o, i, "I", unit(arg(a, i, "m"), arg(a, i, "r0")))
            elif ti.static(todo == 2):
                put(o, i, "f", unit(arg(a, i, "m"), arg(a, i, "g")))
            elif ti.static(todo == 3):
                put(o, i, "F", unit(arg(a, i, "f")))
            elif ti.static(todo == 4):
                put(o, i, "tau", unit(arg(a, i, "p"), arg(a, i, "x"), arg(a, i, "R"), arg(a, i, "r0"),
                                      arg(a, i, "f")))
            elif ti.static(todo == 5):
                x_new, P_new = unit(arg(a, i, "x"), arg(a, i, "P"), arg(a, i, "F"), arg(a, i, "M"),
                                    arg(a, i, "dt"))
                put(o, i, "x_new", x_new)
                put(o, i, "P_new", P_new)
            elif ti.static(todo == 6):
                put(o, i, "q_new", unit(arg(a, i, "q"), arg(a, i, "omega"), arg(a, i, "dt")))
            elif ti.static(todo == 7):
                L_new, I_inv, omega = unit(arg(a, i, "L"), arg(a, i, "tau"), arg(a, i, "R"),
                                           arg(a, i, "I0_inv"), arg(a, i, "dt"))
                put(o, i, "L_new", L_new)
                put(o, i, "I_inv", I_inv)
                put(o, i, "omega", omega)

    return run
