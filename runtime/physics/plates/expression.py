"""An expression plate has no closed-form field off the axis here: None."""


def field(table, p, points, part_field):
    return None
