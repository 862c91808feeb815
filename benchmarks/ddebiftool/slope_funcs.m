function [funcs,ip]=slope_funcs()
%% DDE-BIFTOOL functions for the mean-field spring-block model, eqs. 6a-6e,
% in a co-moving frame that removes the neutral translation of m_x:
%   m_x(t) = z(t) + c*t,  c = mean drift velocity of m_x (a free parameter),
% so that m_x(t-tau)-m_x(t) = z(t-tau)-z(t)-c*tau and z' = m_y - c.
% State x = [z; m_y; s_x; s_y; u]; one discrete delay tau (only z is read delayed).
% z -> z+const is still a symmetry; it is removed by the extra condition
% z(0)=0 (sys_cond), with c as the extra free parameter. For a periodic
% orbit, periodicity of z then forces c = <m_y> (mean of m_y over one period).
ip.k=1; ip.tau=2; ip.c=3; ip.a=4; ip.b=5; ip.cc=6; ip.d=7; ip.v=8;
funcs=set_funcs('sys_rhs',@(x,p)slope_rhs(x,p,ip),'sys_tau',@()ip.tau,...
    'sys_cond',@slope_cond,'x_vectorized',true);
end

function y=slope_rhs(x,p,ip)
a=p(ip.a); b=p(ip.b); cc=p(ip.cc); d=p(ip.d); v=p(ip.v); k=p(ip.k);
tau=p(ip.tau); c=p(ip.c);
F1=3*a*v^2-2*b*v+cc;   % F'(v)
q=3*a*v-b;             % (3av-b)
z=x(1,1,:); ztau=x(1,2,:); my=x(2,1,:); sx=x(3,1,:); sy=x(4,1,:); u=x(5,1,:);
G=F1+2*q*my+3*a*(my.^2+sy);
y=cat(1,...
    my-c,...                                                            % (6a)
    -my.*(F1+my.*(q+a*my))-sy.*(q+3*a*my)+k*(ztau-z-c*tau),...          % (6b)
    2*u,...                                                             % (6c)
    -2*sy.*G-2*k*u+2*d,...                                              % (6d)
    -u.*G-k*sx+sy);                                                     % (6e)
end

function [r,J]=slope_cond(pt)
%% pin the translation: z(0)=0 (stst/hopf: x(1); psol: profile(1,1))
J=p_axpy(0,pt,[]);
switch pt.kind
    case {'stst','hopf','fold'}
        r=pt.x(1); J.x(1)=1;
    case 'psol'
        r=pt.profile(1,1); J.profile(1,1)=1;
    otherwise
        error('slope_cond: kind %s not supported',pt.kind);
end
end
