"""A tank with an inlet and an outlet valve and two level switches: the
plant of the closed-loop example (docs/cosimulation.md), as an FMI 2.0
co-simulation FMU made with pythonfmu:

    pythonfmu build -f tank_plant.py      # writes TankPlant.fmu

Inputs: `inlet` and `outlet` (Boolean, the valves open). Outputs: `level`
(0 to 1, the tank's fill), `low_switch` (ON above 10 %), `high_switch` (ON
above 90 %). The inlet fills 0.5/s, the outlet drains 0.25/s.
"""
from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class TankPlant(Fmi2Slave):
    author = "ladderc"
    description = "A tank with an inlet and an outlet valve and two level switches"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.inlet = False
        self.outlet = False
        self.level = 0.0
        self.low_switch = False
        self.high_switch = False
        self.fill_rate = 0.5
        self.drain_rate = 0.25
        self.register_variable(Boolean("inlet", causality=Fmi2Causality.input))
        self.register_variable(Boolean("outlet", causality=Fmi2Causality.input))
        self.register_variable(Real("level", causality=Fmi2Causality.output))
        self.register_variable(Boolean("low_switch", causality=Fmi2Causality.output))
        self.register_variable(Boolean("high_switch", causality=Fmi2Causality.output))
        self.register_variable(Real("fill_rate", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.tunable))
        self.register_variable(Real("drain_rate", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.tunable))

    def do_step(self, current_time, step_size):
        flow = (self.fill_rate if self.inlet else 0.0) - (self.drain_rate if self.outlet else 0.0)
        self.level = min(1.0, max(0.0, self.level + flow * step_size))
        self.low_switch = self.level > 0.1
        self.high_switch = self.level > 0.9
        return True
